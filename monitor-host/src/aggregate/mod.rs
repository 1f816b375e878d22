//! Aggregates over the routes: every aggregate of a set of routes ([`aggregates`]: the §8.1
//! scores, computed there once for the run's [`summary`], each group, the combined row and each
//! compared run), the [`penalty`] re-check (§8), Bench2Drive's metrics ([`bench2drive`],
//! [`ability`], §8.2), the breakdown [`groups`] (§8.3), the comparison of runs ([`compare`]), the
//! [`stored`]-figure check of the inputs (§1.5) and the collision [`trace`]s (§10.2).

pub mod ability;
pub mod aggregates;
pub mod bench2drive;
pub mod compare;
pub mod groups;
pub mod penalty;
pub mod stored;
pub mod summary;
pub mod trace;
