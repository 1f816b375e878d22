//! Aggregates over the rows of a run (`SDS-SPEC.md` v1.2 §8): every aggregate of a set of
//! routes ([`aggregates`]: the §8.1 scores, computed there once for the run's [`summary`], each
//! group, the combined row and each compared run), Bench2Drive's metrics ([`bench2drive`], §8.2),
//! the steps from DS to SDS ([`decomposition`]), the breakdown [`groups`] (§8.3), the comparison
//! of runs ([`compare`], spec v1.3 §11), and the [`report`]
//! model that holds the rows and their aggregates. The rows themselves come from
//! [`crate::route`].

pub mod aggregates;
pub mod bench2drive;
pub mod compare;
pub mod counts;
pub mod decomposition;
pub mod groups;
pub mod motion;
pub mod report;
pub mod summary;
