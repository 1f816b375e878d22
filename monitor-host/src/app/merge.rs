//! Merging the reports of a run scored where its files are (`sds merge`, `sds.merge`,
//! docs/SCORE.md §13.2): the request each front end fills, over [`crate::merge::merge`].

use std::path::PathBuf;

use crate::aggregate::groups::GroupBy;
use crate::input::duplicates::DuplicatePolicy;
use crate::merge::MergeError;
use crate::model::Report;

/// Reports to merge into one.
///
/// ```
/// use monitor_host::app::merge::MergeRequest;
/// use monitor_host::{demo, report, score_run, Inputs, Settings};
///
/// let dir = tempfile::tempdir()?;
/// let run = demo::write(dir.path())?;
/// let whole = score_run(&Inputs { telemetry: Some(run.telemetry), ..Inputs::new([run.results]) },
///                       &Settings::default())?;
/// let part = dir.path().join("part.json");
/// std::fs::write(&part, report::json::json(&whole)?)?;
/// let merged = MergeRequest { by_scenario: true, ..MergeRequest::new(vec![part]) }.merge()?;
/// assert_eq!(merged.summary, whole.summary);
/// assert!(merged.groups.is_some());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MergeRequest {
    /// The parts: JSON reports of `sds score`, in input order.
    pub parts: Vec<PathBuf>,
    /// A route id with a record in two parts.
    pub duplicates: DuplicatePolicy,
    /// Name this machine in the merged report's provenance.
    pub host: bool,
    /// Break the routes down by scenario when the parts were not broken down (the table
    /// formats show the breakdown, as `sds score`'s do).
    pub by_scenario: bool,
}

impl MergeRequest {
    /// The parts, merged with the defaults (`error` on a duplicate, this host named, no
    /// breakdown added).
    pub fn new(parts: Vec<PathBuf>) -> Self {
        MergeRequest {
            parts,
            duplicates: DuplicatePolicy::Error,
            host: true,
            by_scenario: false,
        }
    }

    /// The merged report.
    ///
    /// # Errors
    /// [`MergeError`]: a part that cannot be read, is no report, or disagrees with another.
    pub fn merge(&self) -> Result<Report, MergeError> {
        let mut report = crate::merge::merge(&self.parts, self.duplicates, self.host)?;
        if self.by_scenario && report.groups.is_none() {
            // A breakdown by scenario needs no label map: it cannot be refused.
            report.group(GroupBy::Scenario, None).ok();
        }
        Ok(report)
    }

    /// The long tables of a merged report (docs/TABLES-SCHEMA.md): its routes and events, each as a file
    /// name and its bytes. No frames: a merge reads no telemetry (each part's `--tables` wrote
    /// its own).
    ///
    /// # Errors
    /// A table that cannot be made (its message).
    pub fn long_tables(report: &Report) -> Result<Vec<(&'static str, Vec<u8>)>, String> {
        let mut tables = crate::report::long_tables::long_tables(report, &[])?;
        tables.frames = None;
        tables.files()
    }
}
