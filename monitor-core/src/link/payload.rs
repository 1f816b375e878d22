//! The link's messages: data ids and payload layouts (docs/SCORE.md, "Live link").
//!
//! Every payload is little-endian with a fixed length per data id, so the receiver checks the
//! header's `length` against the data id's before it reads a field. The ids and layouts are the
//! project's own:
//!
//! | data id | name | way | payload bytes |
//! |---|---|---|---|
//! | `0x5344_5301` | start | doer → checker | 104: the monitor's [`Config`] |
//! | `0x5344_5302` | frame | doer → checker | 33: one [`Frame`] |
//! | `0x5344_5303` | end | doer → checker | 4: frame messages the doer sent for the route |
//! | `0x5344_5311` | event | checker → doer | 20: a [`Tagged`] event |
//! | `0x5344_5312` | status | checker → doer | 36: a [`Status`] |
//! | `0x5344_5313` | summary | checker → doer | 96: a [`LinkSummary`] |
//!
//! A frame message is 12 + 33 = 45 bytes: it fits one CAN-FD data field (64 bytes) as it is,
//! and takes 47 bytes on a byte stream (COBS adds one byte, the delimiter one more).
//!
//! The frame layout: `a_lon`, `a_lat`, `a_mag`, `yaw_rate`, `speed`, `lat_err` as f32 at bytes
//! 0, 4, 8, 12, 16, 20 (`lat_err` 0.0 when unknown); collisions `pedestrian`, `vehicle`,
//! `layout`, `workzone` as u16 at 24, 26, 28, 30; flags u8 at 32 (bit 0: `lat_err` known; the
//! other bits 0). The test vector:
//!
//! ```
//! use monitor_core::link::{self, Message};
//! use monitor_core::{Collisions, Frame};
//! let f = Frame { a_lon: -1.5, a_lat: 0.25, a_mag: 1.5, yaw_rate: 10.0, speed: 8.0,
//!                 lat_err: Some(0.5), collisions: Collisions { vehicle: 1, ..Collisions::NONE } };
//! let mut m = [0u8; link::MAX_MESSAGE];
//! let n = link::seal(&Message::Frame(f), 0x0102, &mut m);
//! assert_eq!(n, 45);
//! assert_eq!(m[..n], [
//!     0x00, 0x2D, 0x01, 0x02, 0x53, 0x44, 0x53, 0x02,   // length 45, counter 0x0102, data id
//!     0x03, 0xDC, 0xC3, 0xBE,                           // CRC-32/AUTOSAR
//!     0x00, 0x00, 0xC0, 0xBF,  0x00, 0x00, 0x80, 0x3E,  // a_lon -1.5, a_lat 0.25
//!     0x00, 0x00, 0xC0, 0x3F,  0x00, 0x00, 0x20, 0x41,  // a_mag 1.5, yaw_rate 10
//!     0x00, 0x00, 0x00, 0x41,  0x00, 0x00, 0x00, 0x3F,  // speed 8, lat_err 0.5
//!     0x00, 0x00, 0x01, 0x00,  0x00, 0x00, 0x00, 0x00,  // collisions 0, 1, 0, 0
//!     0x01,                                             // flags: lat_err known
//! ]);
//! assert_eq!(link::decode(&m[..n]).unwrap().1, Message::Frame(f));
//! ```

use crate::comfort::Failures;
use crate::config::{Bounds, Config, Factors, Profile};
use crate::event::{CollisionVerdict, ComfortVerdict, Event, LateralVerdict};
use crate::frame::{Collisions, Frame};
use crate::lateral::Band;
use crate::link::checker::{CheckStatus, StatusCounts};
use crate::link::e2e::{self, E2eError, Header, HEADER_LEN};
use crate::link::framing::{self, MAX_ENCODED};
use crate::summary::{
    CollisionSummary, ComfortSummary, FailureCounts, LateralSummary, RouteSummary,
};

/// Data id of a start message (doer to checker): the monitor's configuration.
pub const DATA_START: u32 = 0x5344_5301;
/// Data id of a frame message (doer to checker): one input frame.
pub const DATA_FRAME: u32 = 0x5344_5302;
/// Data id of an end message (doer to checker): the route is over.
pub const DATA_END: u32 = 0x5344_5303;
/// Data id of an event message (checker to doer).
pub const DATA_EVENT: u32 = 0x5344_5311;
/// Data id of a status message (checker to doer).
pub const DATA_STATUS: u32 = 0x5344_5312;
/// Data id of a summary message (checker to doer): the route's counts.
pub const DATA_SUMMARY: u32 = 0x5344_5313;

const START_LEN: usize = 104;
const FRAME_LEN: usize = 33;
const END_LEN: usize = 4;
const EVENT_LEN: usize = 20;
const STATUS_LEN: usize = 36;
const SUMMARY_LEN: usize = 96;

/// Bytes of the largest message (a start).
pub const MAX_MESSAGE: usize = HEADER_LEN + START_LEN;

/// Payload bytes of a data id, `None` for an id that is not the link's.
const fn payload_len(data_id: u32) -> Option<usize> {
    match data_id {
        DATA_START => Some(START_LEN),
        DATA_FRAME => Some(FRAME_LEN),
        DATA_END => Some(END_LEN),
        DATA_EVENT => Some(EVENT_LEN),
        DATA_STATUS => Some(STATUS_LEN),
        DATA_SUMMARY => Some(SUMMARY_LEN),
        _ => None,
    }
}

/// What the checker says happened, on the frame with counter `counter`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum LinkEvent {
    /// One of the monitor's events (collision, comfort, lateral), exactly as
    /// [`crate::Monitor::push`] or [`crate::Monitor::finish`] gave it.
    Monitor(Event),
    /// The frame starts segment `index` (0-based) of the route: the monitor started afresh.
    Segment {
        /// The segment's index in the route.
        index: u32,
    },
    /// The link became `INVALID`: `bad` of the window's statuses count against it.
    LinkFault {
        /// Statuses in the window that count against the link.
        bad: u32,
    },
    /// The link became `VALID` again.
    LinkRestored {
        /// Statuses in the window that count against the link.
        bad: u32,
    },
}

/// An event and the counter of the frame message that raised it (for the events of a
/// segment's end, its last accepted frame).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Tagged {
    /// Counter of the frame message.
    pub counter: u16,
    /// The event.
    pub event: LinkEvent,
}

/// Whether the checker can see: `Valid` while at most `max_errors` of the last `window`
/// statuses count against the link.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum LinkState {
    /// The checker sees the doer's frames.
    Valid,
    /// Too many of the last statuses were bad: the checker cannot vouch for the route.
    Invalid,
}

/// Where the checker is in a route.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum RouteState {
    /// No route started (after power-on or reset): frames are checked, not monitored.
    Idle,
    /// A route is running.
    Running,
    /// The route ended; its summary was sent.
    Finished,
    /// The last start's configuration was refused: frames are checked, not monitored.
    Refused,
}

/// A status message: the link's state and its counts so far in the route.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Status {
    /// The link's state.
    pub link: LinkState,
    /// The route's state.
    pub route: RouteState,
    /// Counter of the last frame message that passed its check (0 before any).
    pub last_counter: u16,
    /// Check statuses of the route so far.
    pub counts: StatusCounts,
    /// Frames given to the monitor in the route.
    pub accepted: u32,
    /// Segments started in the route.
    pub segments: u32,
}

/// What the checker answers to an end: the route's counts over its segments together.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct LinkSummary {
    /// The monitor's counts, summed over the segments.
    pub route: RouteSummary,
    /// Frames lost inside segments (counter steps above 1 between accepted frames).
    pub gaps: u32,
    /// Segments.
    pub segments: u32,
    /// Check statuses of the route.
    pub counts: StatusCounts,
}

impl LinkSummary {
    /// Adds one segment's monitor summary to the route's (counts summed, as over the segments
    /// of a vehicle log).
    ///
    /// ```
    /// use monitor_core::{link::LinkSummary, RouteSummary};
    /// let mut s = LinkSummary::default();
    /// let seg = RouteSummary { frames: 5, ..RouteSummary::ZERO };
    /// s.add_segment(&seg);
    /// s.add_segment(&seg);
    /// assert_eq!((s.route.frames, s.segments), (10, 2));
    /// ```
    pub fn add_segment(&mut self, seg: &RouteSummary) {
        self.route.merge(seg);
        self.segments = self.segments.saturating_add(1);
    }
}

/// One message of the link, decoded.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Message {
    /// Start a route with this configuration.
    Start(Config),
    /// One frame.
    Frame(Frame),
    /// The route is over.
    End {
        /// Frame messages the doer sent for the route (for the record; the checker counts its own).
        frames: u32,
    },
    /// An event.
    Event(Tagged),
    /// A status.
    Status(Status),
    /// A route's summary.
    Summary(LinkSummary),
}

impl Message {
    /// The message's data id.
    ///
    /// ```
    /// use monitor_core::link::{Message, DATA_END};
    /// assert_eq!(Message::End { frames: 0 }.data_id(), DATA_END);
    /// ```
    pub const fn data_id(&self) -> u32 {
        match self {
            Message::Start(_) => DATA_START,
            Message::Frame(_) => DATA_FRAME,
            Message::End { .. } => DATA_END,
            Message::Event(_) => DATA_EVENT,
            Message::Status(_) => DATA_STATUS,
            Message::Summary(_) => DATA_SUMMARY,
        }
    }
}

/// Why received bytes are not a message of the link.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum DecodeError {
    /// The end-to-end check failed (length or CRC).
    E2e(E2eError),
    /// A data id that is not the link's.
    DataId(u32),
    /// The length is not the data id's, or a field is out of its range (an unknown profile,
    /// event kind or state, flags that are not defined).
    Layout,
}

/// Little-endian writer over a payload (every write is inside the payload's fixed length).
struct Put<'a>(&'a mut [u8], usize);

impl Put<'_> {
    fn bytes(&mut self, b: &[u8]) {
        if let Some(dst) = self.0.get_mut(self.1..self.1 + b.len()) {
            dst.copy_from_slice(b);
        }
        self.1 += b.len();
    }
    fn u8(&mut self, v: u8) {
        self.bytes(&[v]);
    }
    fn u16(&mut self, v: u16) {
        self.bytes(&v.to_le_bytes());
    }
    fn u32(&mut self, v: u32) {
        self.bytes(&v.to_le_bytes());
    }
    fn f32(&mut self, v: f32) {
        self.bytes(&v.to_le_bytes());
    }
    fn f64(&mut self, v: f64) {
        self.bytes(&v.to_le_bytes());
    }
}

/// Little-endian reader; a read past the end is a layout error.
struct Get<'a>(&'a [u8], usize);

impl Get<'_> {
    fn array<const K: usize>(&mut self) -> Result<[u8; K], DecodeError> {
        let s = self.0.get(self.1..self.1 + K).ok_or(DecodeError::Layout)?;
        self.1 += K;
        let mut a = [0u8; K];
        a.copy_from_slice(s);
        Ok(a)
    }
    fn u8(&mut self) -> Result<u8, DecodeError> {
        Ok(self.array::<1>()?[0])
    }
    fn u16(&mut self) -> Result<u16, DecodeError> {
        Ok(u16::from_le_bytes(self.array()?))
    }
    fn u32(&mut self) -> Result<u32, DecodeError> {
        Ok(u32::from_le_bytes(self.array()?))
    }
    fn f32(&mut self) -> Result<f32, DecodeError> {
        Ok(f32::from_le_bytes(self.array()?))
    }
    fn f64(&mut self) -> Result<f64, DecodeError> {
        Ok(f64::from_le_bytes(self.array()?))
    }
}

fn put_summary(p: &mut Put<'_>, r: &RouteSummary) {
    let f = &r.comfort.failed;
    let l = &r.lateral;
    let c = &r.collisions;
    for v in [
        r.frames,
        r.comfort.chunks,
        r.comfort.comfortable,
        f.lon_acc,
        f.lat_acc,
        f.mag_jerk,
        f.lon_jerk,
        f.yaw_acc,
        f.yaw_rate,
        l.chunks,
        l.scored_chunks,
        l.anomalous,
        l.critical,
        c.aligned,
        c.exempt,
        c.nodecel,
    ] {
        p.u32(v);
    }
}

fn get_summary(g: &mut Get<'_>) -> Result<RouteSummary, DecodeError> {
    Ok(RouteSummary {
        frames: g.u32()?,
        comfort: ComfortSummary {
            chunks: g.u32()?,
            comfortable: g.u32()?,
            failed: FailureCounts {
                lon_acc: g.u32()?,
                lat_acc: g.u32()?,
                mag_jerk: g.u32()?,
                lon_jerk: g.u32()?,
                yaw_acc: g.u32()?,
                yaw_rate: g.u32()?,
            },
        },
        lateral: LateralSummary {
            chunks: g.u32()?,
            scored_chunks: g.u32()?,
            anomalous: g.u32()?,
            critical: g.u32()?,
        },
        collisions: CollisionSummary {
            aligned: g.u32()?,
            exempt: g.u32()?,
            nodecel: g.u32()?,
        },
    })
}

fn put_counts(p: &mut Put<'_>, c: &StatusCounts) {
    for s in CheckStatus::ALL {
        p.u32(c.get(s));
    }
}

fn get_counts(g: &mut Get<'_>) -> Result<StatusCounts, DecodeError> {
    let mut c = StatusCounts::default();
    for s in CheckStatus::ALL {
        c.set(s, g.u32()?);
    }
    Ok(c)
}

fn failures_bits(f: &Failures) -> u8 {
    (f.lon_acc as u8)
        | (f.lat_acc as u8) << 1
        | (f.mag_jerk as u8) << 2
        | (f.lon_jerk as u8) << 3
        | (f.yaw_acc as u8) << 4
        | (f.yaw_rate as u8) << 5
}

fn failures_of(b: u8) -> Result<Failures, DecodeError> {
    if b & !0x3F != 0 {
        return Err(DecodeError::Layout);
    }
    let bit = |i: u8| b & (1 << i) != 0;
    Ok(Failures {
        lon_acc: bit(0),
        lat_acc: bit(1),
        mag_jerk: bit(2),
        lon_jerk: bit(3),
        yaw_acc: bit(4),
        yaw_rate: bit(5),
    })
}

fn put_payload(m: &Message, p: &mut Put<'_>) {
    match m {
        Message::Start(c) => {
            let profile = Profile::ALL.iter().position(|x| *x == c.profile);
            p.u8(profile.unwrap_or(0) as u8);
            p.u8(0);
            p.u16(c.chunk_len);
            p.u16(c.min_chunk);
            p.u16(c.decel_window);
            let b = &c.bounds;
            for v in [
                c.dt,
                c.legacy_jerk_spacing,
                b.lon_acc_min,
                b.lon_acc_max,
                b.lat_acc,
                b.mag_jerk,
                b.lon_jerk,
                b.yaw_acc,
                b.yaw_rate,
                c.slack,
                c.anomalous_excess,
                c.critical_excess,
                c.decel_threshold,
                c.stationary_speed,
            ] {
                p.f32(v);
            }
            let f = &c.factors;
            for v in [f.workzone, f.layout, f.nodecel, f.anomalous, f.critical] {
                p.f64(v);
            }
        }
        Message::Frame(f) => {
            for v in [f.a_lon, f.a_lat, f.a_mag, f.yaw_rate, f.speed] {
                p.f32(v);
            }
            p.f32(f.lat_err.unwrap_or(0.0));
            let c = &f.collisions;
            for v in [c.pedestrian, c.vehicle, c.layout, c.workzone] {
                p.u16(v);
            }
            p.u8(f.lat_err.is_some() as u8);
        }
        Message::End { frames } => p.u32(*frames),
        Message::Event(t) => put_event(t, p),
        Message::Status(s) => {
            p.u8(match s.link {
                LinkState::Valid => 0,
                LinkState::Invalid => 1,
            });
            p.u8(match s.route {
                RouteState::Idle => 0,
                RouteState::Running => 1,
                RouteState::Finished => 2,
                RouteState::Refused => 3,
            });
            p.u16(s.last_counter);
            put_counts(p, &s.counts);
            p.u32(s.accepted);
            p.u32(s.segments);
        }
        Message::Summary(s) => {
            put_summary(p, &s.route);
            p.u32(s.gaps);
            p.u32(s.segments);
            put_counts(p, &s.counts);
        }
    }
}

/// Event kinds on the wire.
const KIND_COLLISION: u8 = 1;
const KIND_COMFORT: u8 = 2;
const KIND_LATERAL: u8 = 3;
const KIND_SEGMENT: u8 = 4;
const KIND_FAULT: u8 = 5;
const KIND_RESTORED: u8 = 6;

/// Event layout: kind u8, flags u8, counter u16, then 16 bytes of values by kind (unused bytes
/// 0): collision: frame u32, speed f32, pedestrian, vehicle, layout, workzone u16 (flags bit 0
/// decelerated, bit 1 exempt); comfort: chunk u32, frames u16, failed bounds u8 (bits in report
/// order: lon_acc .. yaw_rate); lateral: chunk u32, max excess f32, band u8 (1 anomalous,
/// 2 critical); segment: index u32; link_fault and link_restored: bad statuses u32.
fn put_event(t: &Tagged, p: &mut Put<'_>) {
    let (kind, flags) = match &t.event {
        LinkEvent::Monitor(Event::Collision(v)) => {
            (KIND_COLLISION, v.decelerated as u8 | (v.exempt as u8) << 1)
        }
        LinkEvent::Monitor(Event::Comfort(_)) => (KIND_COMFORT, 0),
        LinkEvent::Monitor(Event::Lateral(_)) => (KIND_LATERAL, 0),
        LinkEvent::Segment { .. } => (KIND_SEGMENT, 0),
        LinkEvent::LinkFault { .. } => (KIND_FAULT, 0),
        LinkEvent::LinkRestored { .. } => (KIND_RESTORED, 0),
    };
    p.u8(kind);
    p.u8(flags);
    p.u16(t.counter);
    match &t.event {
        LinkEvent::Monitor(Event::Collision(v)) => {
            p.u32(v.frame);
            p.f32(v.speed);
            let c = &v.collisions;
            for n in [c.pedestrian, c.vehicle, c.layout, c.workzone] {
                p.u16(n);
            }
        }
        LinkEvent::Monitor(Event::Comfort(v)) => {
            p.u32(v.chunk);
            p.u16(v.frames);
            p.u8(failures_bits(&v.failed));
        }
        LinkEvent::Monitor(Event::Lateral(v)) => {
            p.u32(v.chunk);
            p.f32(v.max_excess);
            p.u8(match v.band {
                Band::Normal => 0,
                Band::Anomalous => 1,
                Band::Critical => 2,
            });
        }
        LinkEvent::Segment { index: n }
        | LinkEvent::LinkFault { bad: n }
        | LinkEvent::LinkRestored { bad: n } => p.u32(*n),
    }
}

fn get_event(g: &mut Get<'_>) -> Result<Tagged, DecodeError> {
    let kind = g.u8()?;
    let flags = g.u8()?;
    let counter = g.u16()?;
    let event = match kind {
        KIND_COLLISION => {
            if flags & !3 != 0 {
                return Err(DecodeError::Layout);
            }
            LinkEvent::Monitor(Event::Collision(CollisionVerdict {
                frame: g.u32()?,
                speed: g.f32()?,
                collisions: Collisions {
                    pedestrian: g.u16()?,
                    vehicle: g.u16()?,
                    layout: g.u16()?,
                    workzone: g.u16()?,
                },
                decelerated: flags & 1 != 0,
                exempt: flags & 2 != 0,
            }))
        }
        KIND_COMFORT => LinkEvent::Monitor(Event::Comfort(ComfortVerdict {
            chunk: g.u32()?,
            frames: g.u16()?,
            failed: failures_of(g.u8()?)?,
        })),
        KIND_LATERAL => LinkEvent::Monitor(Event::Lateral(LateralVerdict {
            chunk: g.u32()?,
            max_excess: g.f32()?,
            band: match g.u8()? {
                0 => Band::Normal,
                1 => Band::Anomalous,
                2 => Band::Critical,
                _ => return Err(DecodeError::Layout),
            },
        })),
        KIND_SEGMENT => LinkEvent::Segment { index: g.u32()? },
        KIND_FAULT => LinkEvent::LinkFault { bad: g.u32()? },
        KIND_RESTORED => LinkEvent::LinkRestored { bad: g.u32()? },
        _ => return Err(DecodeError::Layout),
    };
    Ok(Tagged { counter, event })
}

fn get_payload(data_id: u32, g: &mut Get<'_>) -> Result<Message, DecodeError> {
    Ok(match data_id {
        DATA_START => {
            let profile = *Profile::ALL
                .get(usize::from(g.u8()?))
                .ok_or(DecodeError::Layout)?;
            let _reserved = g.u8()?;
            let chunk_len = g.u16()?;
            let min_chunk = g.u16()?;
            let decel_window = g.u16()?;
            let dt = g.f32()?;
            let legacy_jerk_spacing = g.f32()?;
            let bounds = Bounds {
                lon_acc_min: g.f32()?,
                lon_acc_max: g.f32()?,
                lat_acc: g.f32()?,
                mag_jerk: g.f32()?,
                lon_jerk: g.f32()?,
                yaw_acc: g.f32()?,
                yaw_rate: g.f32()?,
            };
            Message::Start(Config {
                profile,
                dt,
                legacy_jerk_spacing,
                chunk_len,
                min_chunk,
                bounds,
                slack: g.f32()?,
                anomalous_excess: g.f32()?,
                critical_excess: g.f32()?,
                decel_threshold: g.f32()?,
                decel_window,
                stationary_speed: g.f32()?,
                factors: Factors {
                    workzone: g.f64()?,
                    layout: g.f64()?,
                    nodecel: g.f64()?,
                    anomalous: g.f64()?,
                    critical: g.f64()?,
                },
            })
        }
        DATA_FRAME => {
            let (a_lon, a_lat, a_mag, yaw_rate, speed, lat) =
                (g.f32()?, g.f32()?, g.f32()?, g.f32()?, g.f32()?, g.f32()?);
            let collisions = Collisions {
                pedestrian: g.u16()?,
                vehicle: g.u16()?,
                layout: g.u16()?,
                workzone: g.u16()?,
            };
            let flags = g.u8()?;
            if flags & !1 != 0 {
                return Err(DecodeError::Layout);
            }
            Message::Frame(Frame {
                a_lon,
                a_lat,
                a_mag,
                yaw_rate,
                speed,
                lat_err: (flags & 1 != 0).then_some(lat),
                collisions,
            })
        }
        DATA_END => Message::End { frames: g.u32()? },
        DATA_EVENT => Message::Event(get_event(g)?),
        DATA_STATUS => {
            let link = match g.u8()? {
                0 => LinkState::Valid,
                1 => LinkState::Invalid,
                _ => return Err(DecodeError::Layout),
            };
            let route = match g.u8()? {
                0 => RouteState::Idle,
                1 => RouteState::Running,
                2 => RouteState::Finished,
                3 => RouteState::Refused,
                _ => return Err(DecodeError::Layout),
            };
            Message::Status(Status {
                link,
                route,
                last_counter: g.u16()?,
                counts: get_counts(g)?,
                accepted: g.u32()?,
                segments: g.u32()?,
            })
        }
        DATA_SUMMARY => Message::Summary(LinkSummary {
            route: get_summary(g)?,
            gaps: g.u32()?,
            segments: g.u32()?,
            counts: get_counts(g)?,
        }),
        other => return Err(DecodeError::DataId(other)),
    })
}

/// Writes `message` with its header (counter `counter`) and CRC into `out`, unframed (what a
/// CAN-FD data field carries); returns its length.
pub fn seal(message: &Message, counter: u16, out: &mut [u8; MAX_MESSAGE]) -> usize {
    let id = message.data_id();
    let len = HEADER_LEN + payload_len(id).unwrap_or(0);
    let Some(m) = out.get_mut(..len) else {
        return 0;
    };
    m.fill(0);
    put_payload(message, &mut Put(&mut m[HEADER_LEN..], 0));
    e2e::protect(m, counter, id);
    len
}

/// Writes `message` as it goes on a byte stream: sealed ([`seal`]), COBS-encoded and ended
/// with 0x00. Returns the bytes written.
pub fn encode(message: &Message, counter: u16, out: &mut [u8; MAX_ENCODED]) -> usize {
    let mut m = [0u8; MAX_MESSAGE];
    let n = seal(message, counter, &mut m);
    framing::frame(&m[..n], out).unwrap_or(0)
}

/// Checks and decodes one unframed message: the end-to-end check ([`e2e::check`]), the data id,
/// the length of its payload, then the payload's fields.
///
/// # Errors
/// [`DecodeError`]: whatever fails makes the message's check status `ERROR`.
pub fn decode(message: &[u8]) -> Result<(Header, Message), DecodeError> {
    let header = e2e::check(message).map_err(DecodeError::E2e)?;
    let want = payload_len(header.data_id).ok_or(DecodeError::DataId(header.data_id))?;
    let payload = message.get(HEADER_LEN..).unwrap_or(&[]);
    if payload.len() != want {
        return Err(DecodeError::Layout);
    }
    let m = get_payload(header.data_id, &mut Get(payload, 0))?;
    Ok((header, m))
}
