//! Scoring protocols (docs/PROTOCOLS.md): the *recorded* events of every route rescored
//! under the arithmetic of other evaluators — Bench2Drive (`b2d`), CARLA Leaderboard 2.0
//! (`lb2.0`) and 2.1 (`lb2.1`), LEAD's length-normalised DS (`lead-nds`) and Fail2Drive's
//! success rule (`f2d`). Nothing is re-run: a rescored route holds the same events, counted
//! under other rules. Protocols read records only (no telemetry), so streaming and batch are
//! untouched.
//!
//! One concept per file: the fixed per-event [`terms`], the [`min_speed`] entries that count,
//! the [`outside_lanes`] factor recovered from the recorded penalty, the per-route [`route`]
//! score, the [`aggregate`]s over routes, and the Bench2Drive [`ability_rule`] versions (docs/SCORE.md §10.1).
//!
//! ```
//! use monitor_host::route::protocol::{parse_protocols, Protocol};
//! assert_eq!(parse_protocols("lb2.1,b2d")?, [Protocol::B2d, Protocol::Lb21]);
//! assert_eq!(parse_protocols("all")?.len(), 5);
//! assert!(parse_protocols("none")?.is_empty());
//! assert!(parse_protocols("lb3").is_err());
//! # Ok::<(), String>(())
//! ```

pub mod ability_rule;
pub mod aggregate;
pub mod min_speed;
pub mod outside_lanes;
pub mod route;
pub mod terms;

pub use crate::settings::{parse_protocols, protocols_text, Protocol};
