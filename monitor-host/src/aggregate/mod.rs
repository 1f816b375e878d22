//! Aggregates over the rows of a run (docs/SCORE.md §9): every aggregate of a set of
//! routes ([`aggregates`]: the §8.1 scores, computed there once for the run's [`summary`], each
//! group, the combined row and each compared run), Bench2Drive's metrics ([`bench2drive`], docs/SCORE.md §10.1),
//! the steps from DS to SDS ([`decomposition`]) and the breakdown [`groups`] (docs/SCORE.md §10.2): one run's
//! aggregates. The rows themselves come from [`crate::route`]; the [`crate::model::Report`] that
//! holds rows and aggregates is in [`crate::model`], the comparison of runs in [`crate::stats`].

pub mod aggregates;
pub mod bench2drive;
pub mod counts;
pub mod decomposition;
pub mod groups;
pub mod motion;
pub mod summary;
