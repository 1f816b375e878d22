//! Aggregates over the routes: the benchmark [`summary`] (§8.1), the [`penalty`] re-check (§8)
//! and the breakdown [`groups`] (§8.3).

pub mod groups;
pub mod penalty;
pub mod summary;
