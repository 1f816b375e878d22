//! `sds_event`: what the monitor reports as it happens (a collision verdict, a chunk's comfort
//! verdict, an anomalous or critical lateral chunk).

use monitor_core::{Band, Event, Events, Failures};

use crate::frame::sds_collisions;

/// Which member of an `sds_event` is set: `SDS_EVENT_COLLISION`, `SDS_EVENT_COMFORT` or
/// `SDS_EVENT_LATERAL`.
#[allow(non_camel_case_types)]
pub type sds_event_kind = u32;
/// Not an event (an unused slot).
pub const SDS_EVENT_NONE: sds_event_kind = 0;
/// `collision` is set.
pub const SDS_EVENT_COLLISION: sds_event_kind = 1;
/// `comfort` is set.
pub const SDS_EVENT_COMFORT: sds_event_kind = 2;
/// `lateral` is set.
pub const SDS_EVENT_LATERAL: sds_event_kind = 3;

/// The band of a chunk's maximum lateral excess.
#[allow(non_camel_case_types)]
pub type sds_band = u32;
/// `max_excess <= anomalous_excess` (never in an event).
pub const SDS_BAND_NORMAL: sds_band = 0;
/// `anomalous_excess < max_excess <= critical_excess`.
pub const SDS_BAND_ANOMALOUS: sds_band = 1;
/// `max_excess > critical_excess`.
pub const SDS_BAND_CRITICAL: sds_band = 2;

/// At most one event of each kind per push or finish.
pub const SDS_MAX_EVENTS: usize = 3;

/// The bounds a comfort chunk failed (all false: comfortable).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[allow(non_camel_case_types)]
pub struct sds_failures {
    /// Longitudinal acceleration left `(lon_acc_min, lon_acc_max)`.
    pub lon_acc: bool,
    /// |lateral acceleration| reached its bound.
    pub lat_acc: bool,
    /// |jerk magnitude| reached its bound.
    pub mag_jerk: bool,
    /// |longitudinal jerk| reached its bound.
    pub lon_jerk: bool,
    /// |yaw acceleration| reached its bound.
    pub yaw_acc: bool,
    /// |yaw rate| reached its bound.
    pub yaw_rate: bool,
}

/// The verdict on the collisions of one frame.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[allow(non_camel_case_types)]
pub struct sds_collision_verdict {
    /// Index of the frame in the route (from 0).
    pub frame: u32,
    /// The collisions of that frame.
    pub collisions: sds_collisions,
    /// Speed at impact, m/s.
    pub speed: f32,
    /// Some frame of the window before had `a_lon <= decel_threshold`.
    pub decelerated: bool,
    /// The ego was standing, or this is the route's first frame.
    pub exempt: bool,
    /// `!decelerated && !exempt`: a collision without deceleration (penalised).
    pub nodecel: bool,
}

/// The comfort verdict of one chunk.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[allow(non_camel_case_types)]
pub struct sds_comfort_verdict {
    /// Chunk index (from 0).
    pub chunk: u32,
    /// Frames in the chunk.
    pub frames: u16,
    /// The bounds it failed.
    pub failed: sds_failures,
    /// No bound failed.
    pub comfortable: bool,
}

/// An anomalous or critical lateral chunk.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[allow(non_camel_case_types)]
pub struct sds_lateral_verdict {
    /// Chunk index (from 0; the trailing partial chunk counts).
    pub chunk: u32,
    /// Maximum lateral excess in the chunk, m.
    pub max_excess: f32,
    /// `SDS_BAND_ANOMALOUS` or `SDS_BAND_CRITICAL`.
    pub band: sds_band,
}

/// One event: `kind` says which member is set; the others are zero.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[allow(non_camel_case_types)]
pub struct sds_event {
    /// Which member is set.
    pub kind: sds_event_kind,
    /// Set when `kind == SDS_EVENT_COLLISION`.
    pub collision: sds_collision_verdict,
    /// Set when `kind == SDS_EVENT_COMFORT`.
    pub comfort: sds_comfort_verdict,
    /// Set when `kind == SDS_EVENT_LATERAL`.
    pub lateral: sds_lateral_verdict,
}

/// The events of one push or finish, in the order they happened: `events[0 .. len]`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[allow(non_camel_case_types)]
pub struct sds_events {
    /// Number of events set (0 to `SDS_MAX_EVENTS`).
    pub len: u32,
    /// The events; slots from `len` on are zero.
    pub events: [sds_event; SDS_MAX_EVENTS],
}

fn failures(f: &Failures) -> sds_failures {
    sds_failures {
        lon_acc: f.lon_acc,
        lat_acc: f.lat_acc,
        mag_jerk: f.mag_jerk,
        lon_jerk: f.lon_jerk,
        yaw_acc: f.yaw_acc,
        yaw_rate: f.yaw_rate,
    }
}

impl From<&Event> for sds_event {
    fn from(e: &Event) -> Self {
        let mut out = sds_event::default();
        #[allow(unreachable_patterns)]
        match e {
            Event::Collision(v) => {
                out.kind = SDS_EVENT_COLLISION;
                out.collision = sds_collision_verdict {
                    frame: v.frame,
                    collisions: v.collisions.into(),
                    speed: v.speed,
                    decelerated: v.decelerated,
                    exempt: v.exempt,
                    nodecel: v.nodecel(),
                };
            }
            Event::Comfort(v) => {
                out.kind = SDS_EVENT_COMFORT;
                out.comfort = sds_comfort_verdict {
                    chunk: v.chunk,
                    frames: v.frames,
                    failed: failures(&v.failed),
                    comfortable: v.failed.comfortable(),
                };
            }
            Event::Lateral(v) => {
                out.kind = SDS_EVENT_LATERAL;
                out.lateral = sds_lateral_verdict {
                    chunk: v.chunk,
                    max_excess: v.max_excess,
                    band: match v.band {
                        Band::Normal => SDS_BAND_NORMAL,
                        Band::Anomalous => SDS_BAND_ANOMALOUS,
                        Band::Critical => SDS_BAND_CRITICAL,
                    },
                };
            }
            // A kind this version does not know stays SDS_EVENT_NONE.
            _ => {}
        }
        out
    }
}

impl sds_events {
    /// Sets `self` to `events` in place (every slot: the event, or zero).
    #[inline(always)] // lets the optimiser read the events where push left them (no copies)
    pub(crate) fn set(&mut self, events: &Events) {
        let mut it = events.iter();
        let mut len = 0;
        // The core emits at most one event per kind, three kinds: no event is left over.
        for slot in self.events.iter_mut() {
            *slot = match it.next() {
                Some(e) => {
                    len += 1;
                    e.into()
                }
                None => sds_event::default(),
            };
        }
        self.len = len;
    }
}
