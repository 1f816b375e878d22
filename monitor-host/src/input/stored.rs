//! The stored-figure check (docs/SCORE.md §14.1): the figures an input file stores (a merge
//! output's `driving score` / `success rate` / `eval num`, or a raw file's non-empty
//! `global_record`) beside the ones computed over the same file's records with the run's N.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::input::record::LoadedRecord;
use crate::input::results_file::ResultSet;
use crate::input::warning::Warning;

/// What a file stores.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StoredFigures {
    /// `merged` (a Bench2Drive merge output) or `global_record` (a raw evaluator file).
    #[serde(deserialize_with = "from_name")]
    pub from: crate::named::Name,
    /// Stored driving score (0..100).
    pub driving_score: f64,
    /// Stored success rate in percent (a merge output stores a fraction; null for a
    /// `global_record`, which stores none).
    pub success_rate: Option<f64>,
    /// Stored `eval num`.
    pub eval_num: Option<u64>,
    /// The denominator the stored driving score fits (`N`, `records`, `eval num`, `220`), if any.
    pub denominator: Option<String>,
}

name_field!(from_name, ["merged", "global_record"]);

/// The same figures computed over the file's records.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ComputedFigures {
    /// Σ score_composed / N.
    pub driving_score: Option<f64>,
    /// 100 × successes / N.
    pub success_rate: Option<f64>,
    /// The run's N.
    pub n: usize,
}

/// One input file of the report's `inputs`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct InputReport {
    /// The file as it was found.
    pub file: PathBuf,
    /// Its records.
    pub records: usize,
    /// What it stores (null when nothing).
    pub stored: Option<StoredFigures>,
    /// Computed over its records with the run's N (null when it stores nothing).
    pub computed: Option<ComputedFigures>,
}

/// Builds the `inputs` list of every results set (in input order), with the check's warnings.
/// `records` are every record read (before the duplicates policy), `n` the run's N.
pub fn check_inputs(
    sets: &[ResultSet],
    records: &[LoadedRecord],
    n: usize,
    warnings: &mut Vec<Warning>,
) -> Vec<InputReport> {
    let mut out = Vec::new();
    // Several files: each may be a shard of one run, whose stored figures cover its own records.
    let files: usize = sets.iter().map(|s| s.files.len()).sum();
    for set in sets {
        for f in &set.files {
            let merged = set.merged_totals.iter().find(|t| t.source == f.path);
            let global = set.global_records.iter().find(|g| g.source == f.path);
            let stored = match (merged, global) {
                (Some(m), _) => Some(StoredFigures {
                    from: "merged",
                    driving_score: m.driving_score,
                    success_rate: Some(100.0 * m.success_rate),
                    eval_num: m.eval_num,
                    denominator: None,
                }),
                (None, Some(g)) => Some(StoredFigures {
                    from: "global_record",
                    driving_score: g.driving_score,
                    success_rate: None,
                    eval_num: None,
                    denominator: None,
                }),
                _ => None,
            };
            let Some(mut stored) = stored else {
                out.push(InputReport {
                    file: f.path.clone(),
                    records: f.records,
                    stored: None,
                    computed: None,
                });
                continue;
            };
            let (composed, successes) = totals(records, &f.path);
            let per = |x: f64| (n > 0).then(|| x / n as f64);
            let computed = ComputedFigures {
                driving_score: per(composed),
                success_rate: per(100.0 * successes as f64),
                n,
            };
            stored.denominator = denominator(&stored, composed, f.records, n);
            let said = stored.denominator.clone().map_or_else(
                || "no denominator of N, its records, eval num or 220 fits it".to_string(),
                |d| format!("a mean over {d}"),
            );
            // A shard of a run (one of several files, or a checkpoint whose own `progress`
            // planned fewer routes than N: one GPU's share scored with the whole route XML),
            // its figure a mean over its own records, is not a disagreement: `inputs` shows
            // both figures. A whole run's file that divides by its records instead of N (a
            // merge output missing crashed routes) is still named.
            let share = f.progress.is_some_and(|(_, total)| total < n as u64);
            let shard = (files > 1 || share)
                && f.records < n
                && stored.denominator.as_deref() == Some(&format!("its {} records", f.records));
            if let Some(c) = computed.driving_score.filter(|_| !shard) {
                if (c - stored.driving_score).abs() > stored_precision(stored.driving_score) {
                    warnings.push(Warning::StoredFigures {
                        file: f.path.clone(),
                        what: "driving score",
                        stored: stored.driving_score,
                        stored_denominator: said.clone(),
                        computed: c,
                        n,
                    });
                }
            }
            if let (Some(c), Some(s)) = (computed.success_rate, stored.success_rate) {
                if (c - s).abs() > 100.0 / n as f64 + 1e-9 {
                    warnings.push(Warning::StoredFigures {
                        file: f.path.clone(),
                        what: "success rate",
                        stored: s,
                        stored_denominator: said,
                        computed: c,
                        n,
                    });
                }
            }
            if let Some(e) = stored.eval_num.filter(|&e| e != f.records as u64) {
                warnings.push(Warning::EvalNum {
                    file: f.path.clone(),
                    eval_num: e,
                    records: f.records,
                });
            }
            out.push(InputReport {
                file: f.path.clone(),
                records: f.records,
                stored: Some(stored),
                computed: Some(computed),
            });
        }
    }
    out
}

/// Half a unit of the last decimal a stored figure was written with (`88.452`: 0.0005), from
/// 1e-6 up to 0.005 (two decimals; a whole number is not read as rounded to units): a stored
/// figure rounded for printing agrees with any value that rounds to it.
fn stored_precision(stored: f64) -> f64 {
    let text = stored.to_string();
    let decimals = text.split_once('.').map_or(0, |(_, d)| d.len()).max(2) as i32;
    (0.5 * 10f64.powi(-decimals)).max(1e-6) + 1e-12
}

/// Σ score_composed and successes of one file's valid records, in record order.
fn totals(records: &[LoadedRecord], file: &Path) -> (f64, usize) {
    records
        .iter()
        .filter(|r| r.source == file)
        .filter_map(|r| r.entry.as_ref().ok())
        .fold((0.0, 0), |(c, s), r| {
            (c + r.score_composed, s + usize::from(r.is_success()))
        })
}

/// The first denominator that reproduces the stored driving score (to its printed precision).
fn denominator(s: &StoredFigures, composed: f64, records: usize, n: usize) -> Option<String> {
    let mut candidates = vec![
        (format!("N = {n}"), n),
        (format!("its {records} records"), records),
    ];
    if let Some(e) = s.eval_num {
        candidates.push((format!("eval num = {e}"), e as usize));
    }
    candidates.push(("220 (Bench2Drive's benchmark size)".into(), 220));
    candidates
        .into_iter()
        .find(|(_, d)| *d > 0 && (composed / *d as f64 - s.driving_score).abs() <= 5e-4)
        .map(|(name, _)| name)
}

#[cfg(test)]
mod tests {
    use super::stored_precision;

    #[test]
    fn precision_of_the_stored_figure() {
        assert!((stored_precision(88.452) - 0.0005).abs() < 1e-9);
        assert!((stored_precision(100.0) - 0.005).abs() < 1e-9);
        assert!((stored_precision(45.81313131313131) - 1e-6).abs() < 1e-9);
        // 88.45189 rounds to 88.452; 88.4514 does not
        assert!((88.452f64 - 88.451_894_818).abs() <= stored_precision(88.452));
        assert!((88.452f64 - 88.4514).abs() > stored_precision(88.452));
    }
}
