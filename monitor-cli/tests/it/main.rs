//! One test binary for the `sds` command line, grouped by feature (ripgrep's `tests/` shape):
//! each module holds the tests of one surface, and a regression is named by its finding
//! (`i33_1_...` for item 1 of issue 33, `r3_05_...` for finding 5 of reliability round 3).
#[path = "../common/mod.rs"]
mod common;

mod campaign;
mod compare;
mod hostile;
mod link;
mod mcap;
mod merge;
mod perf;
mod regression;
mod requests;
mod score;
mod seeds;
mod sweep;
mod tables;
mod watch;
