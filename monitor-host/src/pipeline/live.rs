//! Live frame building (docs/SCORE.md §3): a simulator's values one tick at a time (what
//! Bench2Drive's `get_metric_info()` returns: `acceleration`, `angular_velocity`,
//! `forward_vector`, `right_vector`, `location`, and the step) in, the monitor's [`Frame`]s out,
//! the same frames `sds score` and `sds frames` build from `metric_info.json`. The replay
//! ([`crate::pipeline::prepare`]) builds its frames through [`LiveFrames::build`] too: one
//! [`FrameBuilder`] for the signals and speed, one [`Corridor`] for the lateral error (route
//! waypoints or the map's lane, with the town's map when there is one).
//!
//! ```
//! use monitor_core::Collisions;
//! use monitor_host::pipeline::live::{LiveFrames, Tick};
//! use monitor_host::Settings;
//!
//! // A straight route along x (waypoints 5 m apart); the ego drives 0.5 m beside it.
//! let route = [[0.0, 0.0, 0.0], [5.0, 0.0, 0.0], [10.0, 0.0, 0.0]];
//! let mut live = LiveFrames::new(Some(&route), None, &Settings::default())?;
//! let tick = |x: f64| Tick {
//!     acceleration: [0.5, 0.0, 9.8], angular_velocity: [0.0, 0.0, 2.0],
//!     forward_vector: [1.0, 0.0, 0.0], right_vector: [0.0, 1.0, 0.0],
//!     location: [x, 0.5, 0.0],
//! };
//! let f0 = live.push(None, &tick(0.0), Collisions::NONE, None)?;
//! let f1 = live.push(None, &tick(0.5), Collisions::NONE, None)?;
//! assert_eq!((f0.speed, f1.speed, f1.lat_err), (0.0, 10.0, Some(0.5)));
//! assert_eq!(live.last_step(), Some(1)); // steps 0, 1 when none is given
//! // Steps must increase.
//! assert!(live.push(Some(1), &tick(1.0), Collisions::NONE, None).is_err());
//! # Ok::<(), monitor_host::pipeline::live::LiveError>(())
//! ```

use std::path::{Path, PathBuf};
use std::sync::Arc;

use monitor_core::{Collisions, Frame};

use crate::geometry::corridor::{Corridor, LateralSample, ReferenceKind};
use crate::geometry::map::{Map, MapError};
use crate::geometry::town_maps::find_map;
use crate::input::telemetry::{TelemetryError, TelemetryFrame};
use crate::pipeline::frame::FrameBuilder;
use crate::settings::{LateralReference, Settings};

/// One tick's values, as CARLA gives them (3-vectors in f64, world frame). `rotation` is not
/// read: the monitor needs the forward and right vectors, which already carry the heading.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Tick {
    /// `acceleration`, m/s².
    pub acceleration: [f64; 3],
    /// `angular_velocity`, deg/s (the yaw rate is index 2).
    pub angular_velocity: [f64; 3],
    /// `forward_vector`.
    pub forward_vector: [f64; 3],
    /// `right_vector`.
    pub right_vector: [f64; 3],
    /// `location`, m.
    pub location: [f64; 3],
}

impl Tick {
    /// The five vectors in [`TelemetryFrame::FIELDS`] order.
    pub fn raw(&self) -> [[f64; 3]; 5] {
        [
            self.acceleration,
            self.angular_velocity,
            self.forward_vector,
            self.right_vector,
            self.location,
        ]
    }

    /// A tick from the five vectors in [`TelemetryFrame::FIELDS`] order.
    pub fn from_raw(raw: [[f64; 3]; 5]) -> Self {
        let [acceleration, angular_velocity, forward_vector, right_vector, location] = raw;
        Tick {
            acceleration,
            angular_velocity,
            forward_vector,
            right_vector,
            location,
        }
    }
}

/// Why a live monitor cannot be set up, or a tick was refused.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum LiveError {
    /// The map file cannot be read or parsed (naming the file and element).
    #[error(transparent)]
    Map(#[from] MapError),
    /// A folder of maps was given without the town that picks one.
    #[error(
        "{}: a folder of town maps: name the town (e.g. Town04) to pick its map, or give the \
         .xodr file",
        dir.display()
    )]
    NeedsTown {
        /// The folder.
        dir: PathBuf,
    },
    /// The folder has no map of the town (naming where it looked).
    #[error("{0}")]
    NoMap(String),
    /// `lateral_reference = lane` without a map to find the lane in.
    #[error(
        "lateral_reference lane measures the distance to the nearest driving lane of the town's \
         map: give a map (a .xodr file, or a maps folder and the town), or use the route reference"
    )]
    LaneWithoutMap,
    /// A tick's value is not finite, or too large for the monitor's f32.
    #[error(transparent)]
    Telemetry(#[from] TelemetryError),
    /// A tick's step is not after the previous one.
    #[error("step {step}: not after the previous step {last} (steps must increase)")]
    StepOrder {
        /// The step given.
        step: u64,
        /// The previous step.
        last: u64,
    },
}

/// Loads the map of a live route: `path` is a `.xodr` file, or a folder of town maps searched
/// for `town` as `sds score --maps` does.
///
/// # Errors
/// [`LiveError::NeedsTown`] (a folder without a town), [`LiveError::NoMap`] (no map of the
/// town in the folder), [`LiveError::Map`] (the file cannot be read or parsed).
pub fn load_map(path: &Path, town: Option<&str>) -> Result<Map, LiveError> {
    let file = if path.is_dir() {
        let town = town.ok_or_else(|| LiveError::NeedsTown {
            dir: path.to_path_buf(),
        })?;
        find_map(path, town).map_err(LiveError::NoMap)?
    } else {
        path.to_path_buf()
    };
    Ok(Map::load(&file)?)
}

/// Builds one route's frames tick by tick: the signals and speed ([`FrameBuilder`]) and the
/// lateral error against the route or the lane ([`Corridor`]).
#[derive(Debug)]
pub struct LiveFrames<'a> {
    builder: FrameBuilder,
    corridor: Corridor<'a>,
    /// The next frame starts a segment ([`LiveFrames::start_segment`]).
    fresh: bool,
}

/// Where a [`LiveFrames`] was, to go back to when the monitor refuses the frame just built.
#[derive(Clone, Debug)]
pub struct Checkpoint {
    builder: FrameBuilder,
    corridor: Option<usize>,
    fresh: bool,
}

impl LiveFrames<'static> {
    /// A live route: its waypoints `[x, y, z]` (the route XML's positions), if known, and its
    /// town's map, if any; the settings give `dt`, the lateral reference and the lane values.
    ///
    /// # Errors
    /// [`LiveError::LaneWithoutMap`]: the `lane` reference without a map.
    pub fn new(
        route: Option<&[[f64; 3]]>,
        map: Option<Arc<Map>>,
        settings: &Settings,
    ) -> Result<Self, LiveError> {
        if settings.lateral_reference == LateralReference::Lane && map.is_none() {
            return Err(LiveError::LaneWithoutMap);
        }
        let corridor = Corridor::owned(route, map, settings);
        Ok(LiveFrames::with_corridor(corridor, settings.core.dt))
    }
}

impl<'a> LiveFrames<'a> {
    /// Frames measured against `corridor`, `dt` seconds apart per step.
    pub fn with_corridor(corridor: Corridor<'a>, dt: f32) -> Self {
        LiveFrames {
            builder: FrameBuilder::new(dt),
            corridor,
            fresh: false,
        }
    }

    /// What the lateral error is measured against.
    pub fn reference(&self) -> ReferenceKind {
        self.corridor.kind()
    }

    /// The step of the last frame built, if any.
    pub fn last_step(&self) -> Option<u64> {
        self.builder.last_step()
    }

    /// The step of the next frame: `step`, or the previous step + 1 (0 for the first frame).
    pub fn next_step(&self, step: Option<u64>) -> u64 {
        match (step, self.builder.last_step()) {
            (Some(s), _) => s,
            (None, Some(l)) => l.saturating_add(1),
            (None, None) => 0,
        }
    }

    /// Builds the next frame from a telemetry frame (the replay's entry): the lateral error
    /// from the corridor, and its host-side values.
    pub fn build(
        &mut self,
        t: &TelemetryFrame,
        collisions: Collisions,
    ) -> (Frame, Option<LateralSample>) {
        let sample = self.measure(t);
        let frame = self.builder.push(t, sample.map(|s| s.value), collisions);
        (frame, sample)
    }

    /// Builds the next frame from a tick at `step` (see [`LiveFrames::next_step`]). `lat_err`,
    /// when given, is the core's lateral value itself, in place of the corridor's.
    ///
    /// # Errors
    /// [`LiveError::StepOrder`] and [`LiveError::Telemetry`] (naming the step and field);
    /// nothing changes then.
    pub fn push(
        &mut self,
        step: Option<u64>,
        tick: &Tick,
        collisions: Collisions,
        lat_err: Option<f64>,
    ) -> Result<Frame, LiveError> {
        let step = self.next_step(step);
        if let Some(last) = self.builder.last_step().filter(|&l| step <= l) {
            return Err(LiveError::StepOrder { step, last });
        }
        let t = TelemetryFrame::from_raw(step, tick.raw())?;
        let sample = self.measure(&t);
        Ok(self
            .builder
            .push(&t, lat_err.or(sample.map(|s| s.value)), collisions))
    }

    /// Starts a segment of a vehicle log (docs/SCORE.md §2.4): the next frame is a fresh start, its
    /// speed 0 (no predecessor) and its lateral reference acquired anew over the whole rest of
    /// the route, whatever its step.
    pub fn start_segment(&mut self) {
        self.builder.restart();
        self.fresh = true;
    }

    /// The corridor's sample of the next frame: after a gap in the steps, at a first step that
    /// is not 0, or at a segment's first frame, the route search re-acquires the reference (docs/SCORE.md §3,
    /// v1.4).
    fn measure(&mut self, t: &TelemetryFrame) -> Option<LateralSample> {
        if std::mem::take(&mut self.fresh) {
            return self.corridor.sample_reacquiring(t.location, t.z);
        }
        let previous = self.builder.last_step();
        self.corridor.sample_at(t.location, t.z, t.step, previous)
    }

    /// Where this route is, for [`LiveFrames::rewind`].
    pub fn checkpoint(&self) -> Checkpoint {
        Checkpoint {
            builder: self.builder.clone(),
            corridor: self.corridor.position(),
            fresh: self.fresh,
        }
    }

    /// Goes back to a checkpoint: the frames built since are forgotten (a frame the monitor
    /// refused).
    pub fn rewind(&mut self, c: Checkpoint) {
        self.builder = c.builder;
        self.corridor.rewind(c.corridor);
        self.fresh = c.fresh;
    }
}
