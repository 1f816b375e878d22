//! The data model the renderings read: the [`report::Report`] of one run (its rows and
//! aggregates; [`parts::PartInputs`] for a merged one), one route's [`frames::RouteFrames`], a
//! watch round's [`status::RoundStatus`]. It sits above the one-run aggregates ([`crate::aggregate`]) and below the
//! multi-run statistics ([`crate::stats`], which compare reports) and the renderings
//! ([`crate::report`], which read reports and comparisons).

pub mod duration;
pub mod frames;
pub mod parts;
pub mod read;
pub mod report;
pub mod shard_stall;
pub mod status;
pub mod vehicle_log;

pub use report::Report;
