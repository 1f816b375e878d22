//! Evaluator results files: Bench2Drive / CARLA Leaderboard 2.0 checkpoint JSON
//! (docs/SCORE.md §2.1, docs/SCORE.md §2.2 "Directory input").
//!
//! Three shapes are read, all through [`read_results`]:
//! - a raw evaluator file: `{"_checkpoint": {"global_record", "progress", "records": [..]},
//!   "entry_status", ...}`;
//! - a Bench2Drive merged file: `{"_checkpoint": {"records": [..]}, "driving score",
//!   "success rate", "eval num"}`;
//! - a directory tree of per-route raw files ([`crate::input::discovery::json_files`]). Every
//!   file whose top level has `_checkpoint` is read, in byte-wise order of the paths; a merged
//!   file (one with `"driving score"`) beside raw files in its own folder is skipped with a
//!   warning (it was made from them).
//!
//! Records are validated one by one ([`Record::from_value`]): a record with a missing or
//! wrong-typed required field is kept as an invalid entry naming the field, never dropped.
//!
//! ```
//! use monitor_host::input::results_file::read_results;
//! let dir = tempfile::tempdir()?;
//! let file = dir.path().join("endpoint.json");
//! std::fs::write(&file, r#"{"_checkpoint": {"progress": [1, 1], "records": [{
//!     "route_id": "RouteScenario_3564_rep0", "scenario_name": "InvadingTurn_1",
//!     "weather_id": 23, "status": "Completed",
//!     "infractions": {"collisions_layout": [], "min_speed_infractions": ["Average speed is 90.0% of the surrounding traffic's one"]},
//!     "scores": {"score_route": 100, "score_penalty": 1.0, "score_composed": 100.0}}]},
//!     "entry_status": "Finished"}"#)?;
//! let set = read_results(&file)?;
//! assert_eq!(set.records.len(), 1);
//! let record = set.records[0].entry.as_ref().expect("valid record");
//! assert_eq!(record.xml_id(), Some("3564"));
//! assert_eq!(record.scenario_type(), "InvadingTurn");
//! assert_eq!(record.weather_id.as_deref(), Some("23"));
//! assert!(record.is_success());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::collections::HashMap;
use std::fs;
use std::path::{Path, PathBuf};

use serde::de::{DeserializeSeed, Deserializer, MapAccess, SeqAccess, Visitor};
use serde_json::{Map, Value};

use crate::input::record::{expected, kind, InvalidRecord, LoadedRecord, Record};
use crate::input::warning::Warning;
use crate::input::{discovery, json_keys};

/// The totals stored in a Bench2Drive merged file.
#[derive(Debug, Clone, PartialEq)]
pub struct MergedTotals {
    /// `"driving score"` (0..100).
    pub driving_score: f64,
    /// `"success rate"` (0..1, a fraction, as Bench2Drive stores it).
    pub success_rate: f64,
    /// `"eval num"` (the number of records merged), when present.
    pub eval_num: Option<u64>,
    /// The merged file.
    pub source: PathBuf,
}

/// The mean driving score a raw evaluator file stores in a non-empty `global_record`
/// (`scores_mean.score_composed`: the evaluator's mean over the file's own records).
#[derive(Debug, Clone, PartialEq)]
pub struct GlobalRecord {
    /// `global_record.scores_mean.score_composed` (0..100).
    pub driving_score: f64,
    /// The file.
    pub source: PathBuf,
}

/// One results file read, in input order.
#[derive(Debug, Clone, PartialEq)]
pub struct InputFile {
    /// The file as it was found.
    pub path: PathBuf,
    /// Its records (valid or not).
    pub records: usize,
    /// Its `_checkpoint.progress` `[done, total]`, when it holds two whole numbers.
    pub progress: Option<(u64, u64)>,
}

/// Everything [`read_results`] read.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ResultSet {
    /// Input order: files sorted by path, records in file order.
    pub records: Vec<LoadedRecord>,
    /// Human-readable warnings (crashed runs with no records, skipped merged files, duplicate
    /// route ids naming both files, unknown statuses, ignored stored totals).
    pub warnings: Vec<Warning>,
    /// The stored totals of the merged files that were read.
    pub merged_totals: Vec<MergedTotals>,
    /// The stored `global_record` means of raw files of more than one record.
    pub global_records: Vec<GlobalRecord>,
    /// Every results file read, in input order.
    pub files: Vec<InputFile>,
    /// Files in a directory that looked like results but could not be read, with the reason.
    pub broken_files: Vec<(PathBuf, String)>,
    /// Every file read as a candidate results file (with records or not, skipped or not), so
    /// that a front end never writes over one of them.
    pub files_read: Vec<PathBuf>,
}

impl ResultSet {
    /// The valid records, in input order.
    pub fn valid(&self) -> impl Iterator<Item = &Record> {
        self.records.iter().filter_map(|r| r.entry.as_ref().ok())
    }
}

/// Why a results file (or directory) could not be read. Every message names the file.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ResultsError {
    /// The path could not be read.
    #[error("{}: cannot read: {source}", path.display())]
    Io {
        /// The file or directory.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
    /// The file ends before the JSON value is complete.
    #[error("{}: truncated JSON: unexpected end of input at line {line}, column {column}", path.display())]
    TruncatedJson {
        /// The file.
        path: PathBuf,
        /// 1-based line of the end of input.
        line: usize,
        /// 1-based column.
        column: usize,
    },
    /// The file is not valid JSON.
    #[error("{}: invalid JSON at line {line}, column {column}: {message}", path.display())]
    InvalidJson {
        /// The file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// The parser's message.
        message: String,
    },
    /// Valid JSON, but not a checkpoint: a required field is missing or has the wrong type.
    #[error("{}: field {field}: {reason}", path.display())]
    Format {
        /// The file.
        path: PathBuf,
        /// The JSON path of the field, e.g. `_checkpoint.records`.
        field: String,
        /// What is wrong.
        reason: String,
    },
    /// A directory holds no evaluator result file at all.
    #[error("{}: no evaluator result files (*.json with a top-level \"_checkpoint\") found", path.display())]
    NoResults {
        /// The directory.
        path: PathBuf,
    },
}

/// Reads evaluator results from a file (raw or merged) or a directory tree of them.
///
/// A single file that is unreadable, not JSON, or has no `_checkpoint.records` array is an
/// error. In a directory such a file goes to [`ResultSet::broken_files`] (and a warning) and
/// loading continues; a directory without any result file is [`ResultsError::NoResults`].
pub fn read_results(path: &Path) -> Result<ResultSet, ResultsError> {
    let meta = fs::metadata(path).map_err(|source| ResultsError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let mut set = ResultSet::default();
    if meta.is_dir() {
        load_dir(path, &mut set)?;
    } else {
        let file = match parse_file(path) {
            Parsed::Checkpoint(f) => f,
            Parsed::NotCheckpoint(e) | Parsed::Broken(e) => return Err(e),
        };
        add_file(&mut set, path, file);
        set.files_read.push(path.to_path_buf());
    }
    Ok(set)
}

/// A parsed checkpoint file, before record validation.
struct CheckpointFile {
    records: Vec<Result<Record, InvalidRecord>>,
    merged: bool,
    entry_status: Option<String>,
    progress: Option<Vec<Value>>,
    /// `global_record.scores_mean.score_composed`, when the file stores it.
    global_score: Option<f64>,
    top: Map<String, Value>,
}

enum Parsed {
    Checkpoint(CheckpointFile),
    /// Valid JSON without a top-level `_checkpoint` (in a directory: not a results file).
    NotCheckpoint(ResultsError),
    /// Unreadable, invalid JSON, or a `_checkpoint` without a records array.
    Broken(ResultsError),
}

fn parse_file(path: &Path) -> Parsed {
    let bytes = match crate::input::read::read_input(path, crate::input::read::FileKind::Results) {
        Ok(b) => b,
        Err(source) => {
            return Parsed::Broken(ResultsError::Io {
                path: path.to_path_buf(),
                source,
            })
        }
    };
    // The records are read one at a time as the text is parsed: a file of 10,000 records is
    // never held as one JSON tree (4 KB a record) beside its records.
    let mut records_read = None;
    let mut de = serde_json::Deserializer::from_slice(&bytes);
    let parsed = Reading {
        place: Place::Top,
        records: &mut records_read,
    }
    .deserialize(&mut de)
    .and_then(|v| de.end().map(|()| v));
    let value: Value = match parsed {
        Ok(v) => v,
        Err(e) => {
            let err = if e.classify() == serde_json::error::Category::Eof {
                ResultsError::TruncatedJson {
                    path: path.to_path_buf(),
                    line: e.line(),
                    column: e.column(),
                }
            } else {
                ResultsError::InvalidJson {
                    path: path.to_path_buf(),
                    line: e.line(),
                    column: e.column(),
                    message: strip_position(&e.to_string()),
                }
            };
            return Parsed::Broken(err);
        }
    };
    let format = |field: &str, reason: String| ResultsError::Format {
        path: path.to_path_buf(),
        field: field.to_string(),
        reason,
    };
    // Valid JSON by now; a key written twice would be resolved silently (last one wins).
    if let Ok(Some(key)) = json_keys::first_duplicate_key(&bytes) {
        return Parsed::Broken(format(
            &key,
            "duplicate key: an object holds it twice, so the file is ambiguous (the evaluator \
             never writes a key twice)"
                .to_string(),
        ));
    }
    let Value::Object(mut top) = value else {
        return Parsed::NotCheckpoint(format(
            "(top level)",
            format!(
                "expected an object with \"_checkpoint\", got {}",
                kind(&value)
            ),
        ));
    };
    let checkpoint = match top.remove("_checkpoint") {
        None => {
            return Parsed::NotCheckpoint(format("_checkpoint", "missing".to_string()));
        }
        Some(Value::Object(m)) => m,
        Some(v) => return Parsed::Broken(format("_checkpoint", expected("an object", &v))),
    };
    let mut checkpoint = checkpoint;
    let records = match checkpoint.remove("records") {
        None => return Parsed::Broken(format("_checkpoint.records", "missing".to_string())),
        // The array's records were read as it was parsed; its place holds an empty array.
        Some(Value::Array(_)) => records_read.unwrap_or_default(),
        Some(v) => return Parsed::Broken(format("_checkpoint.records", expected("an array", &v))),
    };
    let progress = match checkpoint.remove("progress") {
        Some(Value::Array(a)) => Some(a),
        _ => None,
    };
    let global_score = checkpoint
        .get("global_record")
        .and_then(|g| g.get("scores_mean")?.get("score_composed")?.as_f64());
    let entry_status = top
        .get("entry_status")
        .and_then(Value::as_str)
        .map(String::from);
    Parsed::Checkpoint(CheckpointFile {
        records,
        merged: top.contains_key("driving score"),
        entry_status,
        progress,
        global_score,
        top,
    })
}

/// Where a value sits in a results file: `_checkpoint.records` is read record by record.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Place {
    Top,
    Checkpoint,
    Records,
    Other,
}

/// Parses a JSON value as `serde_json::Value` does, except that the elements of the
/// `_checkpoint.records` array become records as each is parsed (into `records`; the array is
/// left empty in the value).
struct Reading<'a> {
    place: Place,
    records: &'a mut Option<Vec<Result<Record, InvalidRecord>>>,
}

impl<'de> DeserializeSeed<'de> for Reading<'_> {
    type Value = Value;

    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<Value, D::Error> {
        d.deserialize_any(self)
    }
}

impl<'de> Visitor<'de> for Reading<'_> {
    type Value = Value;

    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("any valid JSON value")
    }

    fn visit_bool<E>(self, v: bool) -> Result<Value, E> {
        Ok(Value::Bool(v))
    }

    fn visit_i64<E>(self, v: i64) -> Result<Value, E> {
        Ok(Value::from(v))
    }

    fn visit_u64<E>(self, v: u64) -> Result<Value, E> {
        Ok(Value::from(v))
    }

    fn visit_f64<E>(self, v: f64) -> Result<Value, E> {
        Ok(serde_json::Number::from_f64(v).map_or(Value::Null, Value::Number))
    }

    fn visit_str<E>(self, v: &str) -> Result<Value, E> {
        Ok(Value::String(v.to_string()))
    }

    fn visit_string<E>(self, v: String) -> Result<Value, E> {
        Ok(Value::String(v))
    }

    fn visit_unit<E>(self) -> Result<Value, E> {
        Ok(Value::Null)
    }

    fn visit_none<E>(self) -> Result<Value, E> {
        Ok(Value::Null)
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Value, A::Error> {
        if self.place == Place::Records {
            let mut records = Vec::new();
            while let Some(v) = seq.next_element::<Value>()? {
                records.push(Record::from_value(&v));
            }
            *self.records = Some(records);
            return Ok(Value::Array(Vec::new()));
        }
        let mut out = Vec::new();
        while let Some(v) = seq.next_element::<Value>()? {
            out.push(v);
        }
        Ok(Value::Array(out))
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Value, A::Error> {
        let records = self.records;
        let mut out = Map::new();
        while let Some(key) = map.next_key::<String>()? {
            let place = match (self.place, key.as_str()) {
                (Place::Top, "_checkpoint") => Place::Checkpoint,
                (Place::Checkpoint, "records") => Place::Records,
                _ => Place::Other,
            };
            let v = if place == Place::Other {
                map.next_value::<Value>()?
            } else {
                map.next_value_seed(Reading {
                    place,
                    records: &mut *records,
                })?
            };
            out.insert(key, v);
        }
        Ok(Value::Object(out))
    }
}

/// serde_json appends " at line L column C"; the error variants carry those separately.
fn strip_position(msg: &str) -> String {
    match msg.rfind(" at line ") {
        Some(i) => msg[..i].to_string(),
        None => msg.to_string(),
    }
}

fn add_file(set: &mut ResultSet, path: &Path, file: CheckpointFile) {
    let n = file.records.len();
    let progress_pair = file.progress.as_ref().and_then(|p| match p.as_slice() {
        [a, b] => Some((a.as_u64()?, b.as_u64()?)),
        _ => None,
    });
    set.files.push(InputFile {
        path: path.to_path_buf(),
        progress: progress_pair,
        records: n,
    });
    if let (true, Some(ds)) = (n > 1, &file.global_score) {
        set.global_records.push(GlobalRecord {
            driving_score: *ds,
            source: path.to_path_buf(),
        });
    }
    let progress_text = file.progress.as_ref().map(|p| {
        let parts: Vec<String> = p.iter().map(Value::to_string).collect();
        format!("[{}]", parts.join(", "))
    });
    if n == 0 {
        let unfinished = file
            .entry_status
            .as_deref()
            .is_some_and(|s| s != "Finished")
            || progress_pair.is_some_and(|(i, total)| i < total);
        set.warnings.push(Warning::NoRecords {
            file: path.to_path_buf(),
            entry_status: file.entry_status.clone(),
            progress: progress_text,
            crashed: unfinished,
        });
    } else if let Some((_, total)) = progress_pair {
        if (n as u64) < total {
            set.warnings.push(Warning::Unfinished {
                file: path.to_path_buf(),
                progress: progress_text.unwrap_or_else(|| "?".into()),
                recorded: n,
                total,
            });
        }
    }
    if file.merged {
        match merged_totals(&file.top, path) {
            Ok(t) => set.merged_totals.push(t),
            Err(reason) => set.warnings.push(Warning::StoredTotalsIgnored {
                file: path.to_path_buf(),
                reason,
            }),
        }
    }
    for (index, entry) in file.records.into_iter().enumerate() {
        if let Ok(r) = &entry {
            if r.composed_mismatch() {
                set.warnings.push(Warning::ComposedScore {
                    file: path.to_path_buf(),
                    index,
                    route: r.route_id.clone(),
                    scores: [r.score_route, r.score_penalty, r.score_composed],
                });
            }
            let known = matches!(r.status.as_str(), "Completed" | "Perfect" | "Failed")
                || r.status.starts_with("Failed - ");
            if !known {
                set.warnings.push(Warning::UnknownStatus {
                    file: path.to_path_buf(),
                    index,
                    route: r.route_id.clone(),
                    status: r.status.clone(),
                });
            }
        }
        set.records.push(LoadedRecord {
            source: path.to_path_buf(),
            index,
            records_in_file: n,
            entry,
        });
    }
}

fn merged_totals(top: &Map<String, Value>, path: &Path) -> Result<MergedTotals, String> {
    let num = |key: &str| match top.get(key) {
        None => Err(format!("field \"{key}\": missing")),
        Some(v) => v
            .as_f64()
            .ok_or_else(|| format!("field \"{key}\": {}", expected("a number", v))),
    };
    let driving_score = num("driving score")?;
    let success_rate = num("success rate")?;
    let eval_num = match top.get("eval num") {
        None | Some(Value::Null) => None,
        Some(v) => Some(v.as_u64().ok_or_else(|| {
            format!(
                "field \"eval num\": {}",
                expected("a non-negative integer", v)
            )
        })?),
    };
    Ok(MergedTotals {
        driving_score,
        success_rate,
        eval_num,
        source: path.to_path_buf(),
    })
}

fn load_dir(root: &Path, set: &mut ResultSet) -> Result<(), ResultsError> {
    // The root itself must be listable: an unreadable root is an error, not a warning.
    fs::read_dir(root).map_err(|source| ResultsError::Io {
        path: root.to_path_buf(),
        source,
    })?;
    let found = discovery::json_files(root, &mut set.warnings);
    set.broken_files.extend(found.broken);
    let files = found.files;
    set.files_read.extend(files.iter().cloned());

    let mut parsed = Vec::new();
    for path in files {
        match parse_file(&path) {
            Parsed::Checkpoint(f) => parsed.push((path, f)),
            Parsed::NotCheckpoint(_) => {}
            Parsed::Broken(e) => {
                let reason = e.to_string();
                set.warnings.push(Warning::UnreadableResults {
                    reason: reason.clone(),
                });
                set.broken_files.push((path, reason));
            }
        }
    }
    if parsed.is_empty() && set.broken_files.is_empty() {
        return Err(ResultsError::NoResults {
            path: root.to_path_buf(),
        });
    }
    // A merge output is skipped only beside raw evaluator files in its own folder: it was made
    // from them (docs/SCORE.md §2.2). Elsewhere in the tree it is read.
    let mut raw_per_folder: HashMap<PathBuf, usize> = HashMap::new();
    for (path, f) in &parsed {
        if !f.merged {
            *raw_per_folder
                .entry(parent(path).to_path_buf())
                .or_default() += 1;
        }
    }
    let skip: Vec<bool> = parsed
        .iter()
        .map(|(path, f)| f.merged && raw_per_folder.contains_key(parent(path)))
        .collect();
    for ((path, f), skip) in parsed.into_iter().zip(skip) {
        if skip {
            set.warnings.push(Warning::MergedSkipped {
                raw_files: raw_per_folder[parent(&path)],
                file: path,
            });
        } else {
            add_file(set, &path, f);
        }
    }
    Ok(())
}

fn parent(path: &Path) -> &Path {
    path.parent().unwrap_or_else(|| Path::new(""))
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn good() -> Value {
        json!({
            "index": 0,
            "route_id": "RouteScenario_24206_rep3",
            "scenario_name": "ConstructionObstacle_12",
            "weather_id": "7",
            "save_name": "RouteScenario_24206_rep3_Town12_ConstructionObstacle_12_7_06_17_06_49_04",
            "status": "Completed",
            "num_infractions": 1,
            "infractions": {
                "collisions_layout": [],
                "min_speed_infractions": ["Average speed is 80.5% of the surrounding traffic's one"],
                "route_timeout": []
            },
            "scores": {"score_route": 100, "score_penalty": 1.0, "score_composed": 100.0},
            "meta": {"route_length": 102.063, "duration_game": 200.05, "duration_system": null},
            "town_name": "Town12"
        })
    }

    fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
        let p = dir.join(name);
        if let Some(parent) = p.parent() {
            fs::create_dir_all(parent).unwrap();
        }
        fs::write(&p, text).unwrap();
        p
    }

    #[test]
    fn single_file_errors_name_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let p = write(
            dir.path(),
            "trunc.json",
            "{\"_checkpoint\": {\"records\": [",
        );
        let e = read_results(&p).unwrap_err().to_string();
        assert!(e.contains("trunc.json"), "{e}");
        assert!(
            e.contains("truncated JSON") && e.contains("line 1, column 29"),
            "{e}"
        );

        let p = write(dir.path(), "bad.json", "{\"_checkpoint\": x}");
        let e = read_results(&p).unwrap_err().to_string();
        assert!(
            e.contains("bad.json: invalid JSON at line 1, column 17"),
            "{e}"
        );

        let p = write(dir.path(), "nock.json", "{\"records\": []}");
        let e = read_results(&p).unwrap_err().to_string();
        assert!(e.ends_with("nock.json: field _checkpoint: missing"), "{e}");

        let p = write(
            dir.path(),
            "norec.json",
            "{\"_checkpoint\": {\"records\": {}}}",
        );
        let e = read_results(&p).unwrap_err().to_string();
        assert!(
            e.ends_with("norec.json: field _checkpoint.records: expected an array, got object"),
            "{e}"
        );

        let e = read_results(&dir.path().join("absent.json"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("absent.json: cannot read"), "{e}");
    }

    #[test]
    fn records_kept_in_order_with_invalid_ones() {
        let dir = tempfile::tempdir().unwrap();
        let mut bad = good();
        bad["scores"]["score_route"] = json!("n/a");
        let text = json!({"_checkpoint": {"records": [good(), bad, 7]},
                          "driving score": 1.5, "success rate": 0.25, "eval num": 3})
        .to_string();
        let p = write(dir.path(), "m.json", &text);
        let set = read_results(&p).unwrap();
        assert_eq!(set.records.len(), 3);
        assert!(set.records[0].entry.is_ok());
        assert!(set.records[1].entry.is_err());
        assert!(set.records[2].entry.is_err());
        assert_eq!(set.records[2].index, 2);
        assert!(set
            .records
            .iter()
            .all(|r| r.records_in_file == 3 && r.source == p));
        assert_eq!(set.merged_totals.len(), 1);
        assert_eq!(set.merged_totals[0].driving_score, 1.5);
        assert_eq!(set.merged_totals[0].eval_num, Some(3));
        // Records 0 and 1 share a route id: the duplicates policy decides later (run level).
        assert!(set.warnings.is_empty(), "{:?}", set.warnings);
        assert_eq!(
            set.files,
            [InputFile {
                path: p.clone(),
                records: 3,
                progress: None,
            }]
        );
    }

    #[test]
    fn unknown_status_and_incomplete_progress_warn() {
        let dir = tempfile::tempdir().unwrap();
        let mut r = good();
        r["status"] = json!("Exploded");
        let text = json!({"_checkpoint": {"progress": [1, 4], "records": [r]},
                          "entry_status": "Crashed"})
        .to_string();
        let p = write(dir.path(), "x.json", &text);
        let set = read_results(&p).unwrap();
        assert_eq!(set.records.len(), 1);
        assert!(set
            .warnings
            .iter()
            .any(|w| w.to_string().contains("unknown status \"Exploded\"")));
        assert!(set
            .warnings
            .iter()
            .any(|w| w.to_string().contains("only 1 of 4 routes")));
    }

    #[test]
    fn empty_directory_is_an_error() {
        let dir = tempfile::tempdir().unwrap();
        write(
            dir.path(),
            "a/metric_info.json",
            "{\"_checkpoint\": {\"records\": []}}",
        );
        write(dir.path(), "b/other.json", "[1, 2]");
        write(dir.path(), "notes.txt", "{");
        let e = read_results(dir.path()).unwrap_err();
        assert!(matches!(e, ResultsError::NoResults { .. }), "{e}");
    }
}
