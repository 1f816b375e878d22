//! # monitor-host
//!
//! The library behind the `sds` tool: reads real Bench2Drive / CARLA Leaderboard 2.0 artifacts,
//! turns each route's telemetry into [`monitor_core::Frame`]s, streams them through
//! [`monitor_core::Monitor`], checks every route against a batch reference, and reports per-route
//! and benchmark scores as the project's definition (v1.5, `docs/SCORE.md`) gives them.
//!
//! Each command is one typed request of [`app`] ([`ScoreRequest`], [`CompareRequest`],
//! [`WatchRequest`], [`MergeRequest`], [`FramesRequest`], [`LinkRequest`]), with the options every
//! scored run takes in [`RunSettings`]; the front ends fill one from their own spelling and call
//! it. [`score_run`] (a run at typed [`Settings`], no notes, no labels) stays public for the tests
//! and benchmarks that set a field directly. The `sds` binary, the tests and the bindings hold
//! no scoring logic.
//! The command line itself is the crate `sds-cli` (`monitor-cli/`), whose small library target
//! lets the `sds` binary and the Python package's `sds` command run the same code.
//!
//! Data flows one way, through folders named after the stages:
//!
//! ```text
//! results JSON ─┐  metric_info.json ─┐  route XML ─┐
//!               v                    v             v
//! input/     record, results_file, discovery, duplicates, route_set, stored (docs/SCORE.md §14.1),
//!            telemetry (types; format picks the reader) ← metric_info, lead_infractions,
//!            route_xml, collision, labels           │
//!               │                                   v
//!               │                       geometry/  kinematics, lateral, corridor, maps,
//!               │                                  junctions
//!               v                                   │
//! pipeline/  prepare → align → frame (f32) → replay: Monitor::push / finish → outcome
//!               │                              └─> reference/batch (must agree, docs/SCORE.md §11)
//!               v
//! route/     row per route: penalty re-check (docs/SCORE.md §9), efficiency, abilities (docs/SCORE.md §10.1), traces
//!            (+ protocol/: the records rescored under other evaluators' rules, docs/PROTOCOLS.md)
//!               v
//! aggregate/ one run's aggregates over rows: summary (docs/SCORE.md §10), bench2drive (docs/SCORE.md §10.1), groups (docs/SCORE.md §10.2)
//!               v
//! model/     what renderings read: Report (rows + aggregates), RouteFrames, RoundStatus
//!               v
//! stats/     several reports compared (docs/SCORE.md §10.3)  │  merge/  reports merged (docs/SCORE.md §13.2)
//!               v
//! report/    renderings: json, csv, table, html, figure, trace_csv, status
//!               v
//! app/       the commands every front end calls, one file each with its request: score,
//!            compare, watch (+ the watch's Session and Watcher), merge, frames, link; and run/,
//!            what they share (score_run, label files, saved reports, vehicle logs, reruns, notes)
//!               v
//! cli/       the `sds` command line (and the Python binding, outside this crate): requests
//!            built from their own spelling
//! ```
//!
//! A file imports only from its own stage or those above it in this picture (and `settings`,
//! `warning`); `scripts/module-graph.py` checks it.
//!
//! Around them: [`Settings`] (every setting, typed), [`Inputs`], [`Warning`], [`Error`] (every
//! layer's error type is re-exported here too), and [`demo`] (writes the built-in demo run).
//!
//! ```
//! use monitor_core::Profile;
//! use monitor_host::{demo, report, Inputs, NoProgress, RunSettings, ScoreRequest};
//!
//! let dir = tempfile::tempdir()?;
//! let run = demo::write(dir.path())?;
//! let request = ScoreRequest {
//!     settings: RunSettings { profile: Profile::B2dLegacy, ..RunSettings::default() },
//!     ..ScoreRequest::new(Inputs {
//!         telemetry: Some(run.telemetry),
//!         route_xml: Some(run.routes),
//!         ..Inputs::new([run.results])
//!     })
//! };
//! let report = request.score(&NoProgress)?.report;
//! let json = report::json::json(&report)?;
//! assert!(json.starts_with(b"{\n  \"schema\": \"sds-report/1\""));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![deny(missing_docs)]
// Two audited exceptions are allowed where they are, each with its SAFETY comment: the
// telemetry scanner's ASCII number token (input/metric_info/scan.rs) and the closed-stdout
// check before the runtime starts (monitor-cli/src/output.rs), and glibc's malloc_trim between
// routes (app/run/mod.rs).
#![deny(unsafe_code)]

#[macro_use]
pub mod named;
pub mod aggregate;
pub mod app;
pub mod demo;
pub mod error;
pub mod error_kind;
pub mod geometry;
pub mod input;
pub mod live_link;
pub mod merge;
pub mod model;
pub mod pipeline;
pub mod provenance;
pub use route::protocol;
pub mod reference;
pub mod report;
pub mod route;
pub mod settings;
pub mod stats;
pub mod write;
pub use input::warning;

// The commands' requests and what they return, at the crate root: the stable names every front
// end imports (the modules under `app/` may move).
pub use app::compare::{CompareRequest, CompareWarning, Compared, RunInputs, RunSpec, Seeds};
pub use app::frames::{Frames, FramesRequest};
pub use app::link::{link_config, LinkError, LinkReport, LinkRequest};
pub use app::merge::MergeRequest;
pub use app::run::rerun::{rerun_files, RerunError, RerunFiles};
pub use app::run::scored::{LabelFiles, Scored};
pub use app::run::{
    route_frames, run_frames, score_run, Inputs, NoProgress, Progress, ReplayCache, RouteFrames,
};
pub use app::score::{RequestError, ScoreError, ScoreRequest};
pub use app::watch::watcher::{RoundOutcome, RoundStatus, RouteCache, Watcher};
pub use app::watch::{Session, Step, Stop, Wake, WatchRequest};
pub use demo::DemoError;
pub use error::Error;
pub use error_kind::ErrorKind;
pub use input::labels::LabelsError;
pub use input::lead_infractions::LeadInfractionsError;
pub use input::results_file::ResultsError;
pub use input::route_xml::RouteError;
pub use input::telemetry::TelemetryError;
pub use model::Report;
pub use pipeline::outcome::{RouteState, TelemetryState};
pub use pipeline::replay::Refused;
pub use settings::{RunSettings, Settings, SettingsError};
pub use warning::Warning;
