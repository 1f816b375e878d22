//! The data model the renderings read: the [`report::Report`] of one run (its rows and
//! aggregates). It sits above the one-run aggregates ([`crate::aggregate`]) and below the
//! multi-run statistics ([`crate::stats`], which compare reports) and the renderings
//! ([`crate::report`], which read reports and comparisons).

pub mod report;

pub use report::Report;
