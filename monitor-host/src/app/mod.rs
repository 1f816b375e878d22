//! The run-level doors every front end calls (the `sds` command line, the Python package, the C
//! binding): score a run ([`run`], [`scored`]), compare runs ([`compare_runs`]), keep a run's
//! report current while it is written ([`watch`]). A front end builds the inputs from its own
//! spelling and calls one of these; the orchestration is here, once.

pub mod compare_runs;
pub mod diagnostics;
pub mod frames;
pub mod link;
pub mod merged;
pub mod request;
pub mod rerun;
pub mod run;
pub mod scored;
pub mod scored_by;
pub mod session;
pub mod vehicle_logs;
pub mod watch;
