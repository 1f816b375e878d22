//! # monitor-host
//!
//! The library behind the `sds` tool: reads real Bench2Drive / CARLA Leaderboard 2.0 artifacts,
//! turns each route's telemetry into [`monitor_core::Frame`]s, streams them through
//! [`monitor_core::Monitor`], checks every route against a batch reference, and reports per-route
//! and benchmark scores as the project's definition (v1.5, `docs/SCORE.md`) gives them.
//!
//! One entry point scores a run: [`score_run`] (or [`score_run_with`] to follow its progress);
//! the front ends call the typed requests of [`app`] around it. The `sds` binary, the tests and
//! the bindings hold no scoring logic.
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
//! app/       the doors every front end calls: typed requests (ScoreRequest, CompareRequest,
//!            WatchRequest, MergeRequest), run (score_run), scored, compare_runs, watch, and the
//!            one watch Session
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
//! use monitor_host::{demo, report, score_run, Inputs, Settings};
//!
//! let dir = tempfile::tempdir()?;
//! let run = demo::write(dir.path())?;
//! let mut settings = Settings::default();
//! settings.set("profile", "b2d-legacy")?;
//! let inputs = Inputs {
//!     telemetry: Some(run.telemetry),
//!     route_xml: Some(run.routes),
//!     ..Inputs::new([run.results])
//! };
//! let report = score_run(&inputs, &settings)?;
//! let json = report::json::json(&report)?;
//! assert!(json.starts_with(b"{\n  \"schema\": \"sds-report/1\""));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![deny(missing_docs)]
// Two audited exceptions are allowed where they are, each with its SAFETY comment: the
// telemetry scanner's ASCII number token (input/metric_info/scan.rs) and the closed-stdout
// check before the runtime starts (monitor-cli/src/output.rs), and glibc's malloc_trim between
// routes (app/run.rs).
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

// The run-level doors, also at their earlier paths (`monitor_host::run::...`).
pub use app::compare_runs::CompareRequest;
pub use app::merged::MergeRequest;
pub use app::request::{RequestError, RunSettings, ScoreRequest};
pub use app::session::{Session, WatchRequest};
pub use app::{compare_runs, run, scored, watch};
pub use compare_runs::{compare_runs, Compared, RunInputs, Seeds};
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
pub use run::{
    route_frames, run_frames, score_run, score_run_cached, score_run_with, Inputs, NoProgress,
    Progress, ReplayCache, RouteFrames,
};
pub use scored::{score_labelled, LabelFiles, Scored};
pub use settings::{RunOptions, Settings, SettingsError};
pub use warning::Warning;
pub use watch::{RoundOutcome, RoundStatus, RouteCache, Watcher};
