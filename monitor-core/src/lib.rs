//! # monitor-core
//!
//! A `#![no_std]`, allocation-free streaming monitor for the **SafeDriving Score** (SDS) of the
//! Safe2Drive paper, exactly as the project's definition (v1.5, explained in `docs/SCORE.md`) gives it. It consumes one telemetry frame at
//! a time in fixed memory and bounded time, so the same code runs next to a vehicle stack on a
//! Cortex-M microcontroller and inside the host replay tool.
//!
//! Data flows one way:
//!
//! ```text
//! Frame ──> Monitor::push ──> Events (collision verdict, chunk comfort, lateral band)
//!                │
//!                └──> Monitor::finish ──> RouteSummary ──> score::ds_safe ──> SafeScore
//! ```
//!
//! | spec section | module |
//! |---|---|
//! | 2 per-frame signals | [`signal`], [`frame`] |
//! | 3 chunks | [`monitor`] |
//! | 4 comfort | [`sg`], [`comfort`] |
//! | 5 pre-collision deceleration | [`decel`] |
//! | 6 lateral excess | [`lateral`] |
//! | 7-8 work zone, scores | [`score`] |
//! | defaults and \[decision\]s | [`config`] |
//! | the live link to a safety controller | [`link`] |
//!
//! ```
//! use monitor_core::{score, Config, Frame, Monitor};
//!
//! let mut monitor: Monitor = Monitor::new(Config::DEFAULT)?;
//! for i in 0..40 {
//!     let f = Frame { a_lon: 0.1, speed: 10.0, lat_err: Some(0.2), ..Frame::default() };
//!     for event in &monitor.push(&f)? {
//!         // act on events here (a vehicle-side monitor raises a pin)
//!         let _ = (i, event);
//!     }
//! }
//! let summary = monitor.finish()?.summary;
//! assert_eq!(summary.comfort_score(), Some(1.0));
//! let record = score::RecordScores { score_route: 100.0, score_penalty: 1.0, workzone: 0 };
//! let safe = score::ds_safe(&summary, &record, &monitor.config().factors);
//! assert_eq!(safe.ds_safe, 100.0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Floats: every per-frame computation is f32, calls micromath as a function
//! (`F32Ext::sqrt(x)`) and sums in a fixed order, so host and firmware agree to the bit.
//! Scores are f64, as the evaluator's are.
//!
//! The kernels [`signal`] and [`sg`] are public: they are the shared f32 kernels of docs/SCORE.md §11, which
//! the host's batch reference calls too. The state machine's parts (chunk buffer, deceleration
//! window, lateral chunk) are internal to [`Monitor`].
//!
//! Features: `serde` (default) derives `serde::Serialize` / `Deserialize` on the public types and
//! enables the `json` module (serde-json-core); `defmt` derives `defmt::Format` on the public types.
#![no_std]
#![deny(missing_docs)]
#![forbid(unsafe_code)]

pub mod comfort;
pub mod config;
pub mod decel;
pub mod error;
pub mod event;
pub mod frame;
#[cfg(feature = "serde")]
pub mod json;
pub mod lateral;
pub mod link;
pub mod monitor;
pub mod score;
pub mod sg;
pub mod signal;
pub mod summary;

pub use comfort::Failures;
pub use config::{Bounds, Config, Factors, Profile};
pub use error::{ConfigError, Field, FrameError, MonitorError};
pub use event::{CollisionVerdict, ComfortVerdict, Event, Events, LateralVerdict};
pub use frame::{Collisions, Frame};
#[cfg(feature = "serde")]
pub use json::JsonError;
pub use lateral::Band;
pub use monitor::{Finished, Monitor};
pub use score::{RecordScores, SafeScore};
pub use summary::{CollisionSummary, ComfortSummary, FailureCounts, LateralSummary, RouteSummary};

/// Frames per chunk and in the deceleration window that [`Monitor`] holds by default (the spec's
/// 20 for both).
pub const DEFAULT_CAPACITY: usize = 20;

/// The largest capacity `N` a [`Monitor<N>`] accepts ([`Config::validate`] refuses more with
/// [`ConfigError::Capacity`]), so that its memory is bounded for every `N`:
///
/// - state: `size_of::<Monitor<N>>()` is about `20 N + 260` bytes (664 B for the default
///   `N = 20`, [`MONITOR_SIZE`]; 20.7 KB for `N = 1024`);
/// - stack at a chunk end: four `[f32; N]` work arrays of the comfort check, `16 N` bytes plus a
///   few hundred (measured with the monitor itself on the same stack: under 8 KiB up to
///   `N = 256`, under 52 KiB for `N = 1024`; `examples/stack_probe.rs`).
///
/// `Monitor<65535>` would need about 2.4 MB of stack at a chunk end, more than a default thread
/// has.
pub const MAX_CAPACITY: usize = 1024;

/// Bytes of the default monitor's state (checked at compile time: at most 1 KiB).
pub const MONITOR_SIZE: usize = core::mem::size_of::<Monitor>();
const _: () = assert!(MONITOR_SIZE <= 1024, "the monitor must fit in 1 KiB");
