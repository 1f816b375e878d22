//! Events the monitor emits as they happen, so a vehicle-side monitor can act at once.

use heapless::Vec;

use crate::comfort::Failures;
use crate::frame::Collisions;
use crate::lateral::Band;

/// The verdict on the collisions of one frame (docs/SCORE.md §6). All collisions of a frame share
/// it: they share the frame's speed and the 20 frames before it.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct CollisionVerdict {
    /// Index of the frame in the route (0-based).
    pub frame: u32,
    /// The collisions of that frame.
    pub collisions: Collisions,
    /// Speed at impact, m/s.
    pub speed: f32,
    /// Some frame of the window before had `a_lon <= decel_threshold`.
    pub decelerated: bool,
    /// The ego was standing (`speed < stationary_speed`) or this is the route's first frame.
    pub exempt: bool,
}

impl CollisionVerdict {
    /// A collision *without deceleration*: penalised by `nodecel` per collision.
    ///
    /// ```
    /// use monitor_core::{CollisionVerdict, Collisions};
    /// let v = CollisionVerdict { frame: 9, collisions: Collisions::NONE, speed: 6.0,
    ///                            decelerated: false, exempt: false };
    /// assert!(v.nodecel());
    /// ```
    pub const fn nodecel(&self) -> bool {
        !self.decelerated && !self.exempt
    }
}

/// The comfort verdict of one chunk (docs/SCORE.md §5).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ComfortVerdict {
    /// Chunk index (0-based).
    pub chunk: u32,
    /// Frames in the chunk (the chunk length, or fewer for a short route).
    pub frames: u16,
    /// Bounds the chunk failed; none failed means comfortable.
    pub failed: Failures,
}

/// An anomalous or critical lateral chunk (docs/SCORE.md §7).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct LateralVerdict {
    /// Chunk index (0-based); the trailing partial chunk counts.
    pub chunk: u32,
    /// Maximum lateral excess in the chunk, m.
    pub max_excess: f32,
    /// Its band (never `normal` in an event).
    pub band: Band,
}

/// One thing that happened.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Event {
    /// Collisions in this frame, with their deceleration verdict.
    Collision(CollisionVerdict),
    /// A chunk ended; its comfort verdict.
    Comfort(ComfortVerdict),
    /// A chunk ended with an anomalous or critical lateral excess.
    Lateral(LateralVerdict),
}

/// At most one event of each kind per call: the events of one `push` or `finish`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Events(Vec<Event, 3>);

impl Events {
    /// No event.
    pub const fn new() -> Self {
        Events(Vec::new())
    }

    pub(crate) fn add(&mut self, e: Event) {
        // One event per kind per call, and three kinds: never full.
        let _ = self.0.push(e);
    }

    /// The events, in the order they happened.
    ///
    /// ```
    /// assert!(monitor_core::Events::new().as_slice().is_empty());
    /// ```
    #[inline]
    pub fn as_slice(&self) -> &[Event] {
        &self.0
    }

    /// Number of events.
    #[inline]
    pub fn len(&self) -> usize {
        self.0.len()
    }

    /// True when nothing happened.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// Iterates the events.
    #[inline]
    pub fn iter(&self) -> core::slice::Iter<'_, Event> {
        self.0.iter()
    }
}

impl<'a> IntoIterator for &'a Events {
    type Item = &'a Event;
    type IntoIter = core::slice::Iter<'a, Event>;
    #[inline]
    fn into_iter(self) -> Self::IntoIter {
        self.0.iter()
    }
}
