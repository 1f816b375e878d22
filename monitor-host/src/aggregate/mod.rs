//! Aggregates over the routes: the benchmark [`summary`] (§8.1), the [`penalty`] re-check (§8)
//! the breakdown [`groups`] (§8.3) and the [`stored`]-figure check of the inputs (§1.5).

pub mod groups;
pub mod penalty;
pub mod stored;
pub mod summary;
