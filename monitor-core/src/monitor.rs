//! The streaming state machine: `push` one frame at a time, `finish` the route.

use crate::comfort::ChunkBuffer;
use crate::config::{Config, Profile};
use crate::decel::DecelWindow;
use crate::error::{ConfigError, MonitorError};
use crate::event::{CollisionVerdict, ComfortVerdict, Event, Events, LateralVerdict};
use crate::frame::Frame;
use crate::lateral::{Band, LateralChunk};
use crate::signal;
use crate::summary::{ComfortSummary, RouteSummary};

/// The SDS monitor of one route, holding at most `N` frames per chunk and in the deceleration
/// window (default 20, the spec's values). Fixed size, no allocation, buildable in a `const`.
///
/// ```
/// use monitor_core::{Collisions, Config, Event, Frame, Monitor};
///
/// let mut monitor: Monitor = Monitor::new(Config::DEFAULT).unwrap();
/// let cruise = Frame { speed: 8.0, lat_err: Some(0.1), ..Frame::default() };
/// for _ in 0..30 {
///     monitor.push(&cruise).unwrap();
/// }
/// // A hit at speed, without braking in the 20 frames before.
/// let hit = Frame { collisions: Collisions { vehicle: 1, ..Collisions::NONE }, ..cruise };
/// let events = monitor.push(&hit).unwrap();
/// assert!(matches!(events.as_slice()[0], Event::Collision(v) if v.nodecel()));
///
/// let done = monitor.finish().unwrap();
/// assert_eq!(done.summary.frames, 31);
/// assert_eq!(done.summary.collisions.nodecel, 1);
/// assert_eq!(done.summary.comfort.chunks, 1);      // the trailing 11 frames are dropped
/// assert_eq!(done.summary.lateral.chunks, 2);      // ... but count for lateral excess
/// ```
#[derive(Clone, Debug)]
pub struct Monitor<const N: usize = { crate::DEFAULT_CAPACITY }> {
    config: Config,
    finished: bool,
    /// The current chunk's comfort signals; its length is the frame count of the chunk.
    chunk: ChunkBuffer<N>,
    lateral: LateralChunk,
    decel: DecelWindow<N>,
    summary: RouteSummary,
    /// Comfort counted under a second profile as well ([`Monitor::with_second_profile`]).
    second: Option<SecondComfort>,
}

/// The comfort counts of a second profile, over the same chunks.
#[derive(Clone, Copy, Debug)]
struct SecondComfort {
    profile: Profile,
    comfort: ComfortSummary,
}

/// What [`Monitor::finish`] returns: the events of the last (partial) chunk and the summary.
#[derive(Clone, Debug, PartialEq)]
pub struct Finished {
    /// Events of the route's end: the short route's comfort chunk, the trailing lateral chunk.
    pub events: Events,
    /// The route summary.
    pub summary: RouteSummary,
}

impl<const N: usize> Monitor<N> {
    /// A monitor for one route, after checking `config` against the capacity `N`.
    ///
    /// ```
    /// use monitor_core::{Config, ConfigError, Monitor};
    /// let bad = Config { decel_window: 21, ..Config::DEFAULT };
    /// assert_eq!(Monitor::<20>::new(bad).err(), Some(ConfigError::DecelWindow));
    /// ```
    pub const fn new(config: Config) -> Result<Self, ConfigError> {
        match config.validate(N) {
            Ok(()) => Ok(Self::fresh(config)),
            Err(e) => Err(e),
        }
    }

    /// [`Monitor::new`] for a `static` or `const`: an invalid `config` is a compile-time error
    /// there. At run time use [`Monitor::new`], which returns the error instead of panicking.
    ///
    /// ```
    /// use monitor_core::{Config, Monitor};
    /// static MONITOR: Monitor = Monitor::new_static(Config::DEFAULT);
    /// assert_eq!(MONITOR.frames(), 0);
    /// ```
    pub const fn new_static(config: Config) -> Self {
        if config.validate(N).is_err() {
            panic!("invalid monitor configuration");
        }
        Self::fresh(config)
    }

    const fn fresh(config: Config) -> Self {
        Monitor {
            config,
            finished: false,
            chunk: ChunkBuffer::new(),
            lateral: LateralChunk::new(),
            decel: DecelWindow::new(),
            summary: RouteSummary::ZERO,
            second: None,
        }
    }

    /// Also counts comfort under `profile`, over the same chunks and with the same bounds: for
    /// example Bench2Drive's smoothness (`b2d-legacy`, docs/SCORE.md §10.1) beside the run's own
    /// `physical` comfort. The three accelerations are smoothed once for both profiles, so this
    /// costs far less than a second monitor, and counts exactly what one would.
    ///
    /// ```
    /// use monitor_core::{Config, Frame, Monitor, Profile};
    ///
    /// let turning = Frame { speed: 5.0, yaw_rate: 40.0, ..Frame::default() };
    /// let mut both: Monitor = Monitor::new(Config::DEFAULT).unwrap().with_second_profile(Profile::B2dLegacy);
    /// let legacy = Config { profile: Profile::B2dLegacy, ..Config::DEFAULT };
    /// let mut alone: Monitor = Monitor::new(legacy).unwrap();
    /// for _ in 0..40 {
    ///     both.push(&turning).unwrap();
    ///     alone.push(&turning).unwrap();
    /// }
    /// let done = both.finish().unwrap();
    /// // 40 deg/s is 0.70 rad/s: within the yaw-rate bound, but not in Bench2Drive's deg/s.
    /// assert_eq!(done.summary.comfort.comfortable, 2);
    /// assert_eq!(both.second_comfort(), Some(&alone.finish().unwrap().summary.comfort));
    /// assert_eq!(both.second_comfort().unwrap().comfortable, 0);
    /// ```
    pub const fn with_second_profile(mut self, profile: Profile) -> Self {
        self.second = Some(SecondComfort {
            profile,
            comfort: ComfortSummary::ZERO,
        });
        self
    }

    /// The comfort counts under the second profile ([`Monitor::with_second_profile`]), `None`
    /// when none was asked for. Final after [`Monitor::finish`].
    ///
    /// ```
    /// use monitor_core::Monitor;
    /// assert_eq!(Monitor::default().second_comfort(), None);
    /// ```
    pub const fn second_comfort(&self) -> Option<&ComfortSummary> {
        match &self.second {
            Some(s) => Some(&s.comfort),
            None => None,
        }
    }

    /// The configuration in use.
    pub const fn config(&self) -> &Config {
        &self.config
    }

    /// Frames pushed so far.
    pub const fn frames(&self) -> u32 {
        self.summary.frames
    }

    /// The counts so far (final after [`Monitor::finish`]).
    pub const fn summary(&self) -> &RouteSummary {
        &self.summary
    }

    /// True once [`Monitor::finish`] has run.
    pub const fn is_finished(&self) -> bool {
        self.finished
    }

    /// Starts a new route with the same configuration.
    pub fn reset(&mut self) {
        self.finished = false;
        self.chunk.clear();
        self.lateral = LateralChunk::new();
        self.decel.clear();
        self.summary = RouteSummary::default();
        if let Some(s) = &mut self.second {
            s.comfort = ComfortSummary::ZERO;
        }
    }

    /// Consumes one frame. O(1) except at a chunk's end, where the chunk is filtered.
    ///
    /// On error nothing changes: a bad frame can be skipped or the route ended.
    ///
    /// ```
    /// use monitor_core::{Config, Frame, Monitor, MonitorError};
    /// let mut m: Monitor = Monitor::new(Config::DEFAULT).unwrap();
    /// let bad = Frame { a_lon: f32::INFINITY, ..Frame::default() };
    /// assert!(matches!(m.push(&bad), Err(MonitorError::Frame(_))));
    /// assert_eq!(m.frames(), 0);
    /// ```
    #[inline]
    pub fn push(&mut self, frame: &Frame) -> Result<Events, MonitorError> {
        if self.finished {
            return Err(MonitorError::Finished);
        }
        frame.validate()?;
        let index = self.summary.frames;
        let Some(next) = index.checked_add(1) else {
            return Err(MonitorError::TooManyFrames);
        };
        let c = &self.config;
        let mut events = Events::new();

        // Deceleration: the window holds the frames *before* this one.
        let hits = frame.collisions.total();
        if hits > 0 {
            let decelerated = self
                .decel
                .decelerated(c.decel_window as usize, c.decel_threshold);
            let exempt = index == 0 || frame.speed < c.stationary_speed;
            let verdict = CollisionVerdict {
                frame: index,
                collisions: frame.collisions,
                speed: frame.speed,
                decelerated,
                exempt,
            };
            let s = &mut self.summary.collisions;
            s.aligned = s.aligned.saturating_add(hits);
            if exempt {
                s.exempt = s.exempt.saturating_add(hits);
            } else if !decelerated {
                s.nodecel = s.nodecel.saturating_add(hits);
            }
            events.add(Event::Collision(verdict));
        }
        self.decel.push(frame.a_lon);

        // Comfort signals: only the first chunk_len frames of each chunk are buffered; the yaw
        // rate in deg/s, converted by each profile at the chunk's end.
        self.chunk
            .push(frame.a_lon, frame.a_lat, frame.a_mag, frame.yaw_rate);

        if let Some(lat_err) = frame.lat_err {
            self.lateral.add(signal::excess(lat_err, c.slack));
        }

        self.summary.frames = next;
        if self.chunk.len() >= usize::from(c.chunk_len) {
            self.close_comfort(&mut events);
            self.close_lateral(&mut events);
            self.chunk.clear();
        }
        Ok(events)
    }

    /// Ends the route: scores the short route's comfort chunk (`min_chunk <= frames <
    /// chunk_len`) and the trailing partial lateral chunk, and returns the summary.
    /// A second call returns [`MonitorError::Finished`].
    ///
    /// ```
    /// use monitor_core::{Config, Frame, Monitor};
    /// let mut m: Monitor = Monitor::new(Config::DEFAULT).unwrap();
    /// for _ in 0..6 {
    ///     m.push(&Frame::default()).unwrap();
    /// }
    /// let done = m.finish().unwrap();
    /// assert_eq!(done.summary.comfort_score(), None); // 6 frames: comfort undefined
    /// assert_eq!(done.summary.lateral.chunks, 1);
    /// ```
    pub fn finish(&mut self) -> Result<Finished, MonitorError> {
        if self.finished {
            return Err(MonitorError::Finished);
        }
        let mut events = Events::new();
        let frames = self.summary.frames;
        let partial = !self.chunk.is_empty();
        if frames < u32::from(self.config.chunk_len) && frames >= u32::from(self.config.min_chunk) {
            self.close_comfort(&mut events);
        }
        if partial {
            self.close_lateral(&mut events);
        }
        self.chunk.clear();
        self.finished = true;
        Ok(Finished {
            events,
            summary: self.summary,
        })
    }

    fn close_comfort(&mut self, events: &mut Events) {
        let frames = self.chunk.len() as u16;
        let second = self.second.as_ref().map(|s| s.profile);
        if let Some((failed, also)) = self.chunk.evaluate(&self.config, second) {
            let chunk = self.summary.comfort.chunks;
            self.summary.comfort.count(&failed);
            if let (Some(s), Some(also)) = (&mut self.second, also) {
                s.comfort.count(&also);
            }
            events.add(Event::Comfort(ComfortVerdict {
                chunk,
                frames,
                failed,
            }));
        }
    }

    fn close_lateral(&mut self, events: &mut Events) {
        let s = &mut self.summary.lateral;
        let chunk = s.chunks;
        s.chunks = s.chunks.saturating_add(1);
        if let Some(m) = self.lateral.max() {
            s.scored_chunks = s.scored_chunks.saturating_add(1);
            let band = Band::of(m, &self.config);
            match band {
                Band::Normal => {}
                Band::Anomalous => s.anomalous = s.anomalous.saturating_add(1),
                Band::Critical => s.critical = s.critical.saturating_add(1),
            }
            if band != Band::Normal {
                events.add(Event::Lateral(LateralVerdict {
                    chunk,
                    max_excess: m,
                    band,
                }));
            }
        }
        self.lateral = LateralChunk::new();
    }
}

impl Default for Monitor {
    fn default() -> Self {
        // The defaults are checked valid for the default capacity at compile time (`config`).
        Monitor::fresh(Config::DEFAULT)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::comfort::ChunkBuffer;
    use crate::decel::DecelWindow;
    use crate::lateral::LateralChunk;
    use crate::RouteSummary;

    #[test]
    fn state_layout() {
        // Layout (DESIGN.md), 64-bit host: Config 104 + ChunkBuffer 352 (4 heapless Vec<f32, 20>
        // of 80 + 8) + LateralChunk 8 + DecelWindow 96 (HistoryBuf<f32, 20>) + RouteSummary 64 +
        // Option<SecondComfort> 36 (a profile and a ComfortSummary of 32) + finished 1 = 661,
        // padded to 8: 664.
        let parts = [
            core::mem::size_of::<Config>(),
            core::mem::size_of::<ChunkBuffer<20>>(),
            core::mem::size_of::<LateralChunk>(),
            core::mem::size_of::<DecelWindow<20>>(),
            core::mem::size_of::<RouteSummary>(),
            core::mem::size_of::<Option<SecondComfort>>(),
        ];
        assert_eq!(parts, [104, 352, 8, 96, 64, 36]);
        assert_eq!(crate::MONITOR_SIZE, 664);
    }
}
