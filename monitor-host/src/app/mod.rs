//! The commands, one file each holding its request: what every front end (the `sds` command
//! line, the Python package, the C binding) calls. A front end fills a request from its own
//! spelling and calls it; the orchestration is here, once.
//!
//! - [`score`]: `sds score` ([`score::ScoreRequest`]);
//! - [`compare`]: `sds compare` ([`compare::CompareRequest`]);
//! - [`watch`]: `sds watch` ([`watch::WatchRequest`], the watch's session and its rounds);
//! - [`merge`]: `sds merge` ([`merge::MergeRequest`]);
//! - [`frames`]: `sds frames` ([`frames::FramesRequest`]);
//! - [`link`]: `sds link` and `sds checker` ([`link::LinkRequest`], [`link::link_config`]).
//!
//! What the commands share, and no command itself, is in [`run`]: a run scored route by route,
//! its label files, a saved report read back, vehicle logs, the routes to run again, and the
//! notes about a scored run.

pub mod compare;
pub mod frames;
pub mod link;
pub mod merge;
pub mod run;
pub mod score;
pub mod watch;
