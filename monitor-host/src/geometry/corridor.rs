//! The lane corridor (docs/SCORE.md §3): per frame, how far the ego is from its reference
//! and how much room its lane leaves it, turned into the one lateral value the core takes.
//!
//! The reference is the route ([`LateralReference::Route`]: the route XML's polyline, its
//! junction gaps filled with the map's lane chain where the town has a map) or the nearest
//! driving lane ([`LateralReference::Lane`], with a map only). The slack of frame i is
//! `w_i / 2 - ego_half_width`, `w_i` the width of the lane under the reference point (route) or
//! of the nearest lane (lane), `lane_width` without a map.
//!
//! The core computes `excess = max(0, |v| - slack)` with the *configured* slack, in f32. So that
//! the core and its firmware stay unchanged, a frame whose slack comes from the map is handed
//! `v_i = max(0, |lat_err_i| - slack_i + slack)`, computed in f64 and rounded to f32 once by
//! the frame builder ([`core_value`]); without a map `v_i = lat_err_i` as before. The streaming monitor and the
//! batch reference take the same `v_i`, so they agree bit for bit as before.
//!
//! ```
//! use monitor_host::geometry::corridor::{Corridor, ReferenceKind};
//! use monitor_host::geometry::map::Map;
//! use monitor_host::input::route_xml::parse_route_xml;
//! use monitor_host::Settings;
//!
//! // One road along x, a 4 m driving lane right of it (CARLA y from 0 to 4, centre y = 2).
//! let map = Map::parse(r#"<OpenDRIVE><road id="1" length="100" junction="-1">
//!   <planView><geometry s="0" x="0" y="0" hdg="0" length="100"><line/></geometry></planView>
//!   <lanes><laneSection s="0"><center><lane id="0" type="none"/></center>
//!     <right><lane id="-1" type="driving"><width sOffset="0" a="4" b="0" c="0" d="0"/></lane></right>
//!   </laneSection></lanes></road></OpenDRIVE>"#, "one-lane.xodr")?;
//! // The route XML has a 40 m junction gap from x = 10 to x = 50.
//! let set = parse_route_xml(r#"<routes><route id="1" town="T"><waypoints>
//!   <position x="5" y="2" z="0"/><position x="10" y="2" z="0"/>
//!   <position x="50" y="2" z="0"/><position x="55" y="2" z="0"/></waypoints></route></routes>"#)?;
//! let route = set.get("1");
//! let settings = Settings::default();
//!
//! // A drive 1.5 m right of the lane centre, from x = 5 to x = 30 (inside the gap).
//! let drive = |c: &mut Corridor| (5..=30).map(|x| c.next([x as f64, 3.5], 0.0)).last().unwrap();
//! let mut xml = Corridor::new(route, None, &settings);
//! assert_eq!(xml.kind(), ReferenceKind::Xml);
//! assert_eq!(drive(&mut xml), None); // inside the gap: unknown
//!
//! let mut corridor = Corridor::new(route, Some(&map), &settings);
//! assert_eq!(corridor.kind(), ReferenceKind::MapRoute);
//! // The gap is filled by the lane: 1.5 m off its centre, slack 4 / 2 - 0.93 = 1.07 m, so the
//! // core's excess `|v| - 0.82` comes out at 1.5 - 1.07 = 0.43 m.
//! let v = drive(&mut corridor).unwrap();
//! assert!((v - (1.5 - 1.07 + 0.82)).abs() < 1e-6, "{v}");
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::sync::Arc;

use crate::geometry::lateral::LateralTracker;
use crate::geometry::map::{Map, Projector};
use crate::input::route_xml::RouteRef;
use crate::settings::{LateralReference, Settings};

/// What a route's lateral error was measured against (the report's `lateral.reference`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ReferenceKind {
    /// The route, junction gaps filled by the town's map (`map-route`).
    MapRoute,
    /// The route XML's straight segments, the town has no map (`xml`).
    Xml,
    /// The nearest driving lane of the town's map (`map-lane`).
    MapLane,
    /// No reference: no route XML entry and no usable map (`none`); the lateral error is unknown.
    None,
}

impl ReferenceKind {
    /// The report's name.
    pub fn name(self) -> &'static str {
        match self {
            ReferenceKind::MapRoute => "map-route",
            ReferenceKind::Xml => "xml",
            ReferenceKind::MapLane => "map-lane",
            ReferenceKind::None => "none",
        }
    }

    /// The reference a route gets: `lane` needs a map (else it falls back to `route`); `route`
    /// needs the route's XML entry.
    pub fn of(has_route: bool, has_map: bool, setting: LateralReference) -> Self {
        match (setting, has_route, has_map) {
            (LateralReference::Lane, _, true) => ReferenceKind::MapLane,
            (_, true, true) => ReferenceKind::MapRoute,
            (_, true, false) => ReferenceKind::Xml,
            (_, false, _) => ReferenceKind::None,
        }
    }
}

impl serde::Serialize for ReferenceKind {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

impl<'de> serde::Deserialize<'de> for ReferenceKind {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let all = [
            ReferenceKind::MapRoute,
            ReferenceKind::Xml,
            ReferenceKind::MapLane,
            ReferenceKind::None,
        ];
        let name = crate::named::one_of(d, &all.map(ReferenceKind::name))?;
        Ok(all
            .into_iter()
            .find(|k| k.name() == name)
            .unwrap_or(ReferenceKind::None))
    }
}

/// The reference polyline of a route (docs/SCORE.md §2.3, docs/SCORE.md §14.3): its waypoints, each junction gap (a segment
/// longer than `gap_max`) replaced by the map's lane chain from P to Q when there is one. A gap
/// without a chain stays a straight segment, which [`LateralTracker`] treats as a gap.
///
/// ```
/// use monitor_host::geometry::corridor::reference_polyline;
/// let pts = reference_polyline(&[[0.0, 0.0, 0.0], [20.0, 0.0, 0.0]], 8.0, None);
/// assert_eq!(pts, vec![[0.0, 0.0], [20.0, 0.0]]);
/// ```
pub fn reference_polyline(
    waypoints: &[[f64; 3]],
    gap_max: f64,
    map: Option<&Map>,
) -> Vec<[f64; 2]> {
    let mut out: Vec<[f64; 2]> = Vec::with_capacity(waypoints.len());
    for (i, w) in waypoints.iter().enumerate() {
        if i > 0 {
            let p = waypoints[i - 1];
            if (w[0] - p[0]).hypot(w[1] - p[1]) > gap_max {
                if let Some(chain) = map.and_then(|m| m.fill_gap(p, *w)) {
                    // From P onto the chain (its first point is P's projection), along it, and
                    // off it to Q: every piece is scored like any other segment.
                    out.extend(chain);
                }
            }
        }
        out.push([w[0], w[1]]);
    }
    out
}

/// The value handed to the core for a frame `lat_err_i` m from its reference whose slack is
/// `slack_i` (from the map's lane width), when the core subtracts the configured `core_slack`:
/// `max(0, |lat_err_i| - slack_i + core_slack)`, in f64 (the frame builder rounds it to f32
/// once). Its excess in the core, `max(0, |v| - core_slack)`, is the frame's own excess to f32
/// rounding; a frame inside its lane stays at zero excess.
///
/// ```
/// use monitor_host::geometry::corridor::core_value;
/// assert_eq!(core_value(2.0, 1.07, 0.82), 2.0 - 1.07 + f64::from(0.82f32));
/// assert_eq!(core_value(0.5, 1.9, 0.82), 0.0); // deep inside a wide lane
/// ```
pub fn core_value(lat_err: f64, slack_i: f64, core_slack: f32) -> f64 {
    (lat_err.abs() - slack_i + f64::from(core_slack)).max(0.0)
}

/// Follows one route's frames and yields the core's lateral value per frame (see the module
/// docs). Built once per route; each frame costs the tracker's bounded search plus, with a map,
/// one [`Projector`] query.
#[derive(Debug)]
pub struct Corridor<'a> {
    kind: ReferenceKind,
    tracker: Option<LateralTracker<'a>>,
    projector: Option<Projector<'a>>,
    lane_width: f64,
    ego_half_width: f64,
    core_slack: f32,
    /// `core_slack` as the user wrote it (`settings::decimal`), computed once: formatting it per
    /// frame cost ~4 % of a replay.
    core_slack_decimal: f64,
    reacquire_steps: u64,
}

impl Corridor<'static> {
    /// A corridor that owns its reference: the route's waypoints `[x, y, z]` (the route XML's
    /// positions, or a live front end's), if any, and the town's map, if any. The same corridor
    /// as [`Corridor::new`] gives for a route XML entry with these waypoints, for a front end
    /// that keeps it across calls (the live monitor).
    ///
    /// ```
    /// use monitor_host::geometry::corridor::{Corridor, ReferenceKind};
    /// use monitor_host::Settings;
    /// let route = [[0.0, 0.0, 0.0], [5.0, 0.0, 0.0]];
    /// let mut c = Corridor::owned(Some(&route), None, &Settings::default());
    /// assert_eq!((c.kind(), c.next([1.0, 0.5], 0.0)), (ReferenceKind::Xml, Some(0.5)));
    /// ```
    pub fn owned(
        waypoints: Option<&[[f64; 3]]>,
        map: Option<Arc<Map>>,
        settings: &Settings,
    ) -> Self {
        let kind = ReferenceKind::of(
            waypoints.is_some(),
            map.is_some(),
            settings.lateral_reference,
        );
        let tracker = match (kind, waypoints) {
            (ReferenceKind::MapRoute, Some(w)) => Some(map_route(w, map.as_deref(), settings)),
            (ReferenceKind::Xml, Some(w)) => Some(LateralTracker::owned(
                w.iter().map(|p| [p[0], p[1]]).collect(),
                settings.gap_max,
                settings.lookahead,
            )),
            _ => None,
        };
        Corridor::with(kind, tracker, map.map(Projector::shared), settings)
    }
}

/// The tracker of the map route: the waypoints, junction gaps filled by the map's lane chain.
fn map_route(
    waypoints: &[[f64; 3]],
    map: Option<&Map>,
    settings: &Settings,
) -> LateralTracker<'static> {
    let polyline = reference_polyline(waypoints, settings.gap_max, map);
    LateralTracker::owned(polyline, settings.gap_max, settings.lookahead)
}

impl<'a> Corridor<'a> {
    /// The corridor of `route` (its XML entry, if any) in a town whose map is `map` (if any).
    pub fn new(route: Option<&'a RouteRef>, map: Option<&'a Map>, settings: &Settings) -> Self {
        let kind = ReferenceKind::of(route.is_some(), map.is_some(), settings.lateral_reference);
        let tracker = match (kind, route) {
            (ReferenceKind::MapRoute, Some(r)) => Some(map_route(&r.waypoints_3d(), map, settings)),
            (ReferenceKind::Xml, Some(r)) => {
                Some(LateralTracker::new(r, settings.gap_max, settings.lookahead))
            }
            _ => None,
        };
        Corridor::with(kind, tracker, map.map(Projector::new), settings)
    }

    fn with(
        kind: ReferenceKind,
        tracker: Option<LateralTracker<'a>>,
        projector: Option<Projector<'a>>,
        settings: &Settings,
    ) -> Self {
        Corridor {
            kind,
            tracker,
            projector,
            lane_width: settings.lane_width,
            ego_half_width: settings.ego_half_width,
            core_slack: settings.core.slack,
            core_slack_decimal: crate::settings::decimal(settings.core.slack),
            reacquire_steps: settings.reacquire_steps,
        }
    }

    /// The position of the route search (its matched segment), to go back to with
    /// [`Corridor::rewind`] when a frame is refused after it was measured. The map's projection
    /// keeps no state that changes an answer.
    pub fn position(&self) -> Option<usize> {
        self.tracker.as_ref().map(LateralTracker::segment)
    }

    /// Goes back to a [`Corridor::position`].
    pub fn rewind(&mut self, position: Option<usize>) {
        if let (Some(t), Some(m)) = (self.tracker.as_mut(), position) {
            t.set_segment(m);
        }
    }

    /// The reference this route uses.
    pub fn kind(&self) -> ReferenceKind {
        self.kind
    }

    /// The core's lateral value of a frame at `loc` (CARLA x, y) and height `z`, in f64 (to be
    /// rounded to f32 once), or `None` when the lateral error is unknown (no reference, or an
    /// unfilled junction gap).
    pub fn next(&mut self, loc: [f64; 2], z: f64) -> Option<f64> {
        self.sample(loc, z).map(|s| s.value)
    }

    /// Like [`Corridor::next`], with the host-side values behind the core's value: what
    /// `sds frames` prints for each frame.
    pub fn sample(&mut self, loc: [f64; 2], z: f64) -> Option<LateralSample> {
        self.measure(loc, z, false)
    }

    /// [`Corridor::sample`] of a frame at `step` whose previous frame was at `previous` (`None`
    /// for the first frame): the route search re-acquires the reference after a gap of more than
    /// `reacquire_steps` steps or at a first step that is not 0 (docs/SCORE.md §3, v1.4,
    /// [`crate::geometry::lateral::reacquires`]). Every front end (replay, live monitor, watch)
    /// measures its frames through this, so their lateral values agree.
    ///
    /// ```
    /// use monitor_host::geometry::corridor::Corridor;
    /// use monitor_host::Settings;
    /// // A straight 100 m route of 2 m pieces; telemetry that starts at step 480, at x = 61.
    /// let route: Vec<[f64; 3]> = (0..=50).map(|i| [2.0 * f64::from(i), 0.0, 0.0]).collect();
    /// let mut c = Corridor::owned(Some(&route), None, &Settings::default());
    /// let s = c.sample_at([61.0, 0.3], 0.0, 480, None).unwrap();
    /// assert!((s.lat_err - 0.3).abs() < 1e-12);
    /// ```
    pub fn sample_at(
        &mut self,
        loc: [f64; 2],
        z: f64,
        step: u64,
        previous: Option<u64>,
    ) -> Option<LateralSample> {
        let rest = crate::geometry::lateral::reacquires(step, previous, self.reacquire_steps);
        self.measure(loc, z, rest)
    }

    /// [`Corridor::sample`] searching the whole rest of the route (docs/SCORE.md §3, v1.4): the first frame
    /// of a vehicle log's segment (docs/SCORE.md §2.4), whatever its step.
    pub fn sample_reacquiring(&mut self, loc: [f64; 2], z: f64) -> Option<LateralSample> {
        self.measure(loc, z, true)
    }

    /// One frame's sample; `rest`: search the whole rest of the route.
    fn measure(&mut self, loc: [f64; 2], z: f64, rest: bool) -> Option<LateralSample> {
        let search = |t: &mut LateralTracker<'a>| {
            if rest {
                t.reacquire_with_point(loc)
            } else {
                t.next_with_point(loc)
            }
        };
        match self.kind {
            ReferenceKind::None => None,
            ReferenceKind::Xml => {
                let (d, _) = search(self.tracker.as_mut()?)?;
                Some(LateralSample {
                    lat_err: d,
                    // The configured slack, as the user wrote it (the core subtracts its f32).
                    slack: self.core_slack_decimal,
                    lane_width: None,
                    value: d,
                })
            }
            ReferenceKind::MapRoute => {
                let (d, foot) = search(self.tracker.as_mut()?)?;
                let (w, from_map) = self.width_at(foot, z);
                Some(self.with_width(d, w, from_map))
            }
            ReferenceKind::MapLane => {
                let p = self.projector.as_mut()?.project(loc[0], loc[1], z)?;
                Some(self.with_width(p.distance_2d, p.width, true))
            }
        }
    }

    /// A sample whose slack comes from a lane `w` m wide.
    fn with_width(&self, d: f64, w: f64, from_map: bool) -> LateralSample {
        let slack = w / 2.0 - self.ego_half_width;
        LateralSample {
            lat_err: d,
            slack,
            lane_width: Some(LaneWidth { width: w, from_map }),
            value: core_value(d, slack, self.core_slack),
        }
    }

    /// The width of the lane under `point` (with the frame's height): the map's (`true`), else
    /// `lane_width` (`false`).
    fn width_at(&mut self, point: [f64; 2], z: f64) -> (f64, bool) {
        match self
            .projector
            .as_mut()
            .and_then(|p| p.width(point[0], point[1], z))
        {
            Some(w) => (w, true),
            None => (self.lane_width, false),
        }
    }
}

/// One frame's lateral values in the host (f64): the distance to the reference, the slack it is
/// allowed, and the value handed to the core ([`core_value`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LateralSample {
    /// Unsigned distance to the reference (route or lane), m.
    pub lat_err: f64,
    /// The frame's slack, m: `lane width / 2 - ego half width`, or the configured slack against
    /// the route XML alone.
    pub slack: f64,
    /// The lane width behind the slack, when there is one.
    pub lane_width: Option<LaneWidth>,
    /// The core's lateral value (before its rounding to f32).
    pub value: f64,
}

/// A lane width and where it came from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LaneWidth {
    /// Width, m.
    pub width: f64,
    /// From the town's map (`true`) or the `lane_width` setting where the map has no lane.
    pub from_map: bool,
}
