//! Which `sds` and which settings scored each run of a comparison (docs/SCORE.md §13.2:
//! "`sds compare` and `merge` show when runs were scored by different versions or settings").
//!
//! `sds compare` scores results files itself, all with one version and one set of settings; a
//! run may also be a report scored elsewhere (an `sds score` or `sds merge` JSON report: a
//! sharded evaluation merged on its cluster), read back as `sds merge` reads a part. Such runs
//! may come from another `sds` version or other settings (another `slack`, another profile),
//! and their figures are then not comparable one to one: [`differences`] says so, naming the
//! runs and the first setting that differs.
//!
//! ```
//! use monitor_host::app::run::scored_by::{differences, ScoredBy};
//! let a = ScoredBy { sds_version: Some("0.1.0".into()),
//!                    config: serde_json::json!({"profile": "physical", "slack": 0.82}) };
//! let b = ScoredBy { config: serde_json::json!({"profile": "physical", "slack": 0.5}), ..a.clone() };
//! let w = differences(&[("base", &a), ("new", &b), ("again", &a)]);
//! assert_eq!(w.len(), 1);
//! assert!(w[0].contains("runs base and new were scored with different settings: slack is 0.82 in base and 0.5 in new"));
//! ```

use std::io::Read as _;
use std::path::Path;

use serde_json::Value;

use crate::app::run::{Inputs, Progress};
use crate::error::Error;
use crate::input::duplicates::DuplicatePolicy;
use crate::input::results_file::ResultsError;
use crate::merge::{self, first_difference, MergeError};
use crate::model::report::{Report, SCHEMA};
use crate::settings::Settings;

/// The version and settings that scored one run.
#[derive(Clone, Debug, PartialEq)]
pub struct ScoredBy {
    /// The `sds` version (`inputs.provenance.sds_version`; `None` for a report without it).
    pub sds_version: Option<String>,
    /// The report's `config` block (every scoring setting).
    pub config: Value,
}

impl ScoredBy {
    /// A report scored here and now.
    pub fn of(report: &Report) -> ScoredBy {
        ScoredBy {
            sds_version: Some(report.inputs.provenance.sds_version.clone()),
            config: serde_json::to_value(&report.config).unwrap_or(Value::Null),
        }
    }
}

/// Whether `file` is an `sds` JSON report (top-level `"schema": "sds-report/1"`, as `sds score`
/// and `sds merge` write it) rather than an evaluator's results file. The first bytes decide
/// for the files `sds` and the evaluators write; any other JSON file is read for its `schema`.
pub fn is_report(file: &Path) -> bool {
    if file.is_dir() {
        return false;
    }
    let mut head = Vec::with_capacity(256);
    let read = std::fs::File::open(file).and_then(|f| f.take(256).read_to_end(&mut head));
    if read.is_err() {
        return false;
    }
    let text = String::from_utf8_lossy(&head);
    let text = text.trim_start_matches('\u{feff}').trim_start();
    if !text.starts_with('{') {
        return false;
    }
    let field = |t: &str| {
        t.split_once("\"schema\"").is_some_and(|(_, rest)| {
            rest.trim_start()
                .trim_start_matches(':')
                .trim_start()
                .starts_with(&format!("\"{SCHEMA}\""))
        })
    };
    if field(text) {
        return true;
    }
    if text.contains("\"_checkpoint\"") {
        return false;
    }
    #[derive(serde::Deserialize)]
    struct Schema {
        schema: Option<String>,
    }
    std::fs::read(file).ok().is_some_and(|bytes| {
        let bytes = bytes.strip_prefix("\u{feff}".as_bytes()).unwrap_or(&bytes);
        serde_json::from_slice::<Schema>(bytes).is_ok_and(|s| s.schema.as_deref() == Some(SCHEMA))
    })
}

/// An `sds` report given as a run, read back as `sds merge` reads one part (its rows
/// aggregated again: the report `sds score` wrote), with the version and settings that scored
/// it.
///
/// # Errors
/// [`ResultsError::Io`] when it cannot be read, [`ResultsError::Format`] when it is not a
/// report `sds` can read back (naming the field).
pub fn read_report(file: &Path, host: bool) -> Result<(Report, ScoredBy), ResultsError> {
    let format = |field: &str, reason: String| ResultsError::Format {
        path: file.to_path_buf(),
        field: field.into(),
        reason,
    };
    let part = merge::read_part(file).map_err(|e| match e {
        MergeError::Read { file, source } => ResultsError::Io { path: file, source },
        MergeError::NotAReport { why, .. } => format("(an sds report)", why),
        e => format("(an sds report)", crate::error::message(&e)),
    })?;
    let by = ScoredBy {
        sds_version: part.inputs.sds_version.clone(),
        config: part.config.clone(),
    };
    let report = merge::merge_parts(vec![part], DuplicatePolicy::Error, host)
        .map_err(|e| format("(an sds report)", crate::error::message(&e)))?;
    Ok((report, by))
}

/// A run of `sds compare`: read back when it is one `sds` report ([`read_report`]), else
/// scored here ([`crate::app::run::score_run_with`]); with the version and settings that scored it.
///
/// # Errors
/// As [`read_report`] ([`Error::Results`]) or [`crate::app::run::score_run_with`].
pub(crate) fn score_or_read(
    inputs: &Inputs,
    settings: &Settings,
    progress: &dyn Progress,
) -> Result<(Report, ScoredBy), Error> {
    match inputs.results.as_slice() {
        [f] if is_report(f) => read_report(f, settings.provenance_host).map_err(Error::Results),
        _ => crate::app::run::score_run_with(inputs, settings, progress).map(|report| {
            let by = ScoredBy::of(&report);
            (report, by)
        }),
    }
}

/// One warning per run scored by another `sds` version or other settings than the first run,
/// naming both runs, the versions, or the first setting that differs.
pub fn differences(runs: &[(&str, &ScoredBy)]) -> Vec<String> {
    let Some((first, by)) = runs.first() else {
        return Vec::new();
    };
    let version = |v: &Option<String>| v.clone().unwrap_or_else(|| "an unknown version".into());
    let mut out = Vec::new();
    for (name, other) in &runs[1..] {
        if other.sds_version != by.sds_version {
            out.push(format!(
                "runs {first} and {name} were scored by different sds versions ({} and {}): \
                 one version's figures may differ from another's; score both with one version \
                 to compare them one to one",
                version(&by.sds_version),
                version(&other.sds_version)
            ));
        }
        if let Some((setting, a, b)) = first_difference(&by.config, &other.config, "") {
            out.push(format!(
                "runs {first} and {name} were scored with different settings: {setting} is {a} \
                 in {first} and {b} in {name}; their figures are not comparable one to one \
                 (score both with the same settings)"
            ));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nested_and_absent_settings_are_named() {
        let a = serde_json::json!({"bounds": {"yaw_rate": 1.0, "jerk": 2.0}, "x": 1});
        let b = serde_json::json!({"bounds": {"yaw_rate": 1.0, "jerk": 3.0}, "x": 1});
        assert_eq!(
            first_difference(&a, &b, ""),
            Some(("bounds.jerk".into(), "2.0".into(), "3.0".into()))
        );
        let c = serde_json::json!({"bounds": {"yaw_rate": 1.0, "jerk": 2.0}});
        assert_eq!(
            first_difference(&a, &c, ""),
            Some(("x".into(), "1".into(), "absent".into()))
        );
        let w = differences(&[
            (
                "a",
                &ScoredBy {
                    sds_version: None,
                    config: a.clone(),
                },
            ),
            (
                "b",
                &ScoredBy {
                    sds_version: None,
                    config: b,
                },
            ),
        ]);
        assert!(
            w[0].contains("bounds.jerk is 2.0 in a and 3.0 in b"),
            "{w:?}"
        );
    }

    #[test]
    fn an_unknown_version_differs_from_a_known_one() {
        let a = ScoredBy {
            sds_version: Some("0.1.0".into()),
            config: Value::Null,
        };
        let b = ScoredBy {
            sds_version: None,
            ..a.clone()
        };
        let w = differences(&[("a", &a), ("b", &b)]);
        assert_eq!(w.len(), 1);
        assert!(w[0].contains("(0.1.0 and an unknown version)"), "{}", w[0]);
        assert!(differences(&[("a", &a)]).is_empty());
    }

    #[test]
    fn a_results_file_is_not_a_report() {
        let dir = tempfile::tempdir().unwrap();
        let r = dir.path().join("r.json");
        std::fs::write(&r, "\u{feff}{\n  \"schema\": \"sds-report/1\", \"x\": 1}").unwrap();
        assert!(is_report(&r));
        std::fs::write(&r, "{\"_checkpoint\": {\"records\": []}}").unwrap();
        assert!(!is_report(&r));
        std::fs::write(&r, "{\"schema\": \"sds-compare/1\"}").unwrap();
        assert!(!is_report(&r));
        // Keys in another order (a report rewritten by a script).
        let late = format!(
            "{{\"a\": \"{}\", \"schema\": \"sds-report/1\"}}",
            "x".repeat(300)
        );
        std::fs::write(&r, late).unwrap();
        assert!(is_report(&r));
        assert!(!is_report(dir.path()));
        assert!(!is_report(&dir.path().join("absent.json")));
    }
}
