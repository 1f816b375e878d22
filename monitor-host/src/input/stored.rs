//! The stored-figure check (`SDS-SPEC.md` v1.2 §1.5): the figures an input file stores (a merge
//! output's `driving score` / `success rate` / `eval num`, or a raw file's non-empty
//! `global_record`) beside the ones computed over the same file's records with the run's N.

use std::path::{Path, PathBuf};

use serde::Serialize;

use crate::input::record::LoadedRecord;
use crate::input::results_file::ResultSet;
use crate::warning::Warning;

/// What a file stores.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct StoredFigures {
    /// `merged` (a Bench2Drive merge output) or `global_record` (a raw evaluator file).
    pub from: &'static str,
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

/// The same figures computed over the file's records.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ComputedFigures {
    /// Σ score_composed / N.
    pub driving_score: Option<f64>,
    /// 100 × successes / N.
    pub success_rate: Option<f64>,
    /// The run's N.
    pub n: usize,
}

/// One input file of the report's `inputs`.
#[derive(Clone, Debug, PartialEq, Serialize)]
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
            if let Some(c) = computed.driving_score {
                if (c - stored.driving_score).abs() > 1e-6 {
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
