//! Evaluator results: Bench2Drive / CARLA Leaderboard 2.0 checkpoint JSON (`SDS-SPEC.md` §1.1,
//! §1.2 "Directory input", §8 success rule).
//!
//! Three shapes are read, all through [`load`]:
//! - a raw evaluator file: `{"_checkpoint": {"global_record", "progress", "records": [..]},
//!   "entry_status", ...}`;
//! - a Bench2Drive merged file: `{"_checkpoint": {"records": [..]}, "driving score",
//!   "success rate", "eval num"}`;
//! - a directory tree of per-route raw files. Every `*.json` except `metric_info.json` and
//!   `infractions.json` whose top level has `_checkpoint` is read; when raw files exist, merged
//!   files (those with `"driving score"`) are skipped with a warning.
//!
//! Records are validated one by one: a record with a missing or wrong-typed required field is
//! kept as an [`InvalidRecord`] naming the field, never dropped.
//!
//! ```
//! use monitor_host::results;
//! let dir = tempfile::tempdir()?;
//! let file = dir.path().join("endpoint.json");
//! std::fs::write(&file, r#"{"_checkpoint": {"progress": [1, 1], "records": [{
//!     "route_id": "RouteScenario_3564_rep0", "scenario_name": "InvadingTurn_1",
//!     "weather_id": 23, "status": "Completed",
//!     "infractions": {"collisions_layout": [], "min_speed_infractions": ["Average speed is 90.0% of the surrounding traffic's one"]},
//!     "scores": {"score_route": 100, "score_penalty": 1.0, "score_composed": 100.0}}]},
//!     "entry_status": "Finished"}"#)?;
//! let set = results::load(&file)?;
//! assert_eq!(set.records.len(), 1);
//! let record = set.records[0].entry.as_ref().expect("valid record");
//! assert_eq!(record.xml_id(), Some("3564"));
//! assert_eq!(record.scenario_type(), "InvadingTurn");
//! assert_eq!(record.weather_id.as_deref(), Some("23"));
//! assert!(record.is_success());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::collections::{HashMap, HashSet};
use std::fmt::Write as _;
use std::fs;
use std::path::{Path, PathBuf};

use serde_json::{Map, Value};

/// The 12 infraction lists of a Leaderboard 2.0 record, in the spec's order (§1.1).
pub const KNOWN_LISTS: [&str; 12] = [
    "collisions_pedestrian",
    "collisions_vehicle",
    "collisions_layout",
    "red_light",
    "stop_infraction",
    "outside_route_lanes",
    "min_speed_infractions",
    "yield_emergency_vehicle_infractions",
    "scenario_timeouts",
    "route_dev",
    "vehicle_blocked",
    "route_timeout",
];

/// The one infraction list that does not prevent a success (§8).
pub const MIN_SPEED_LIST: &str = "min_speed_infractions";

/// A record's infraction lists: the 12 known lists by name plus any unknown extra lists, the
/// latter in file order. A known list absent from the file is empty.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Infractions {
    known: [Vec<String>; 12],
    unknown: Vec<(String, Vec<String>)>,
}

impl Infractions {
    /// No infractions at all.
    pub fn new() -> Self {
        Self::default()
    }

    /// Builds the lists from `(name, entries)` pairs; unknown names are kept in the given order.
    /// A name given twice appends to the earlier list.
    pub fn from_lists<I, N>(lists: I) -> Self
    where
        I: IntoIterator<Item = (N, Vec<String>)>,
        N: Into<String>,
    {
        let mut inf = Self::default();
        for (name, entries) in lists {
            inf.push_list(name.into(), entries);
        }
        inf
    }

    fn push_list(&mut self, name: String, mut entries: Vec<String>) {
        if let Some(i) = KNOWN_LISTS.iter().position(|k| *k == name) {
            self.known[i].append(&mut entries);
        } else if let Some((_, list)) = self.unknown.iter_mut().find(|(n, _)| *n == name) {
            list.append(&mut entries);
        } else {
            self.unknown.push((name, entries));
        }
    }

    /// The entries of list `name` (known or unknown); an empty slice if the list is absent.
    pub fn list(&self, name: &str) -> &[String] {
        if let Some(i) = KNOWN_LISTS.iter().position(|k| *k == name) {
            return &self.known[i];
        }
        self.unknown
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, l)| l.as_slice())
            .unwrap_or(&[])
    }

    /// The unknown extra lists, in file order.
    pub fn unknown(&self) -> impl Iterator<Item = (&str, &[String])> {
        self.unknown.iter().map(|(n, l)| (n.as_str(), l.as_slice()))
    }

    /// Every list: the 12 known ones in [`KNOWN_LISTS`] order, then the unknown ones.
    pub fn all(&self) -> impl Iterator<Item = (&str, &[String])> {
        KNOWN_LISTS
            .iter()
            .zip(self.known.iter())
            .map(|(n, l)| (*n, l.as_slice()))
            .chain(self.unknown())
    }

    /// True when every list except `min_speed_infractions` is empty, unknown lists included
    /// (the infraction half of the §8 success rule).
    pub fn clean_except_min_speed(&self) -> bool {
        self.all()
            .all(|(name, list)| name == MIN_SPEED_LIST || list.is_empty())
    }
}

/// `meta` of a record: lengths in metres, durations in seconds. Absent or null fields are `None`.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Meta {
    /// `meta.route_length` (m).
    pub route_length: Option<f64>,
    /// `meta.duration_game` (simulated s).
    pub duration_game: Option<f64>,
    /// `meta.duration_system` (wall-clock s).
    pub duration_system: Option<f64>,
}

/// One validated route record (§1.1). Unknown extra keys are ignored.
#[derive(Debug, Clone, PartialEq)]
pub struct Record {
    /// `RouteScenario_<xmlid>_rep<k>`.
    pub route_id: String,
    /// e.g. `ConstructionObstacle_1`; empty when the record has none.
    pub scenario_name: String,
    /// Weather preset id; numbers in the file are turned into strings.
    pub weather_id: Option<String>,
    /// `<route_id>_<Town>_<scenario_name>_<weather_id>_<timestamp>`: the telemetry folder name.
    pub save_name: Option<String>,
    /// e.g. `Town12`.
    pub town_name: Option<String>,
    /// `Completed`, `Perfect` or `Failed - <reason>`.
    pub status: String,
    /// The infraction lists.
    pub infractions: Infractions,
    /// `scores.score_route` (0..100).
    pub score_route: f64,
    /// `scores.score_penalty` (authoritative, §8).
    pub score_penalty: f64,
    /// `scores.score_composed`.
    pub score_composed: f64,
    /// `meta`.
    pub meta: Meta,
}

impl Record {
    /// `<xmlid>` of `RouteScenario_<xmlid>_rep<k>`, or `None` when `route_id` has another form.
    pub fn xml_id(&self) -> Option<&str> {
        let rest = self.route_id.strip_prefix("RouteScenario_")?;
        let (id, rep) = rest.rsplit_once("_rep")?;
        let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
        (digits(id) && digits(rep)).then_some(id)
    }

    /// The scenario type: `scenario_name` without its trailing `_<N>` suffix
    /// (`ConstructionObstacle_1` → `ConstructionObstacle`). A name without such a suffix is
    /// returned whole.
    pub fn scenario_type(&self) -> &str {
        match self.scenario_name.rsplit_once('_') {
            Some((head, n)) if !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()) => head,
            _ => &self.scenario_name,
        }
    }

    /// §8 success: status `Completed` or `Perfect`, and every infraction list except
    /// `min_speed_infractions` empty (unknown extra lists included).
    pub fn is_success(&self) -> bool {
        matches!(self.status.as_str(), "Completed" | "Perfect")
            && self.infractions.clean_except_min_speed()
    }

    /// Validates one record value. The error's `reason` names the offending field, e.g.
    /// `field scores.score_route: expected a number, got string`.
    pub fn from_value(value: &Value) -> Result<Record, InvalidRecord> {
        let Some(obj) = value.as_object() else {
            return Err(InvalidRecord {
                route_id: None,
                reason: format!("record: expected an object, got {}", kind(value)),
            });
        };
        let route_id = obj
            .get("route_id")
            .and_then(Value::as_str)
            .map(String::from);
        let fail = |reason: String| InvalidRecord {
            route_id: route_id.clone(),
            reason,
        };
        let route_id_s = req_str(obj, "route_id", "route_id").map_err(fail)?;
        let status = req_str(obj, "status", "status").map_err(fail)?;
        let scores = match obj.get("scores") {
            None => return Err(fail(missing("scores"))),
            Some(Value::Object(m)) => m,
            Some(v) => return Err(fail(wrong("scores", "an object", v))),
        };
        let score_route = req_num(scores, "score_route", "scores.score_route").map_err(fail)?;
        let score_penalty =
            req_num(scores, "score_penalty", "scores.score_penalty").map_err(fail)?;
        let score_composed =
            req_num(scores, "score_composed", "scores.score_composed").map_err(fail)?;
        let infractions = match obj.get("infractions") {
            None => return Err(fail(missing("infractions"))),
            Some(Value::Object(m)) => parse_infractions(m).map_err(fail)?,
            Some(v) => return Err(fail(wrong("infractions", "an object", v))),
        };
        let scenario_name = opt_str(obj, "scenario_name", "scenario_name")
            .map_err(fail)?
            .unwrap_or_default();
        let weather_id = match obj.get("weather_id") {
            None | Some(Value::Null) => None,
            Some(Value::String(s)) => Some(s.clone()),
            Some(Value::Number(n)) => Some(number_to_id(n)),
            Some(v) => return Err(fail(wrong("weather_id", "a string or number", v))),
        };
        let save_name = opt_str(obj, "save_name", "save_name").map_err(fail)?;
        let town_name = opt_str(obj, "town_name", "town_name").map_err(fail)?;
        let meta = match obj.get("meta") {
            None | Some(Value::Null) => Meta::default(),
            Some(Value::Object(m)) => Meta {
                route_length: opt_num(m, "route_length", "meta.route_length").map_err(fail)?,
                duration_game: opt_num(m, "duration_game", "meta.duration_game").map_err(fail)?,
                duration_system: opt_num(m, "duration_system", "meta.duration_system")
                    .map_err(fail)?,
            },
            Some(v) => return Err(fail(wrong("meta", "an object", v))),
        };
        Ok(Record {
            route_id: route_id_s,
            scenario_name,
            weather_id,
            save_name,
            town_name,
            status,
            infractions,
            score_route,
            score_penalty,
            score_composed,
            meta,
        })
    }
}

/// A record that failed validation; kept so that it is reported, never dropped.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct InvalidRecord {
    /// The record's `route_id` when it has a string one.
    pub route_id: Option<String>,
    /// What is wrong, naming the field (`field scores.score_route: expected a number, got string`).
    pub reason: String,
}

impl std::fmt::Display for InvalidRecord {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match &self.route_id {
            Some(id) => write!(f, "route {id}: {}", self.reason),
            None => write!(f, "{}", self.reason),
        }
    }
}

/// One record as read, with where it came from.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadedRecord {
    /// The file it came from.
    pub source: PathBuf,
    /// Its position in that file's `_checkpoint.records` (0-based).
    pub index: usize,
    /// How many records that file holds (telemetry beside the file is only used when it is 1).
    pub records_in_file: usize,
    /// The validated record, or why it is invalid.
    pub entry: Result<Record, InvalidRecord>,
}

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

/// Everything [`load`] read.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ResultSet {
    /// Input order: files sorted by path, records in file order.
    pub records: Vec<LoadedRecord>,
    /// Human-readable warnings (crashed runs with no records, skipped merged files, duplicate
    /// route ids naming both files, unknown statuses, ignored stored totals).
    pub warnings: Vec<String>,
    /// The stored totals of the merged files that were read.
    pub merged_totals: Vec<MergedTotals>,
    /// Files in a directory that looked like results but could not be read, with the reason.
    pub broken_files: Vec<(PathBuf, String)>,
}

impl ResultSet {
    /// The valid records, in input order.
    pub fn valid(&self) -> impl Iterator<Item = &Record> {
        self.records.iter().filter_map(|r| r.entry.as_ref().ok())
    }
}

/// Why a results file (or directory) could not be read. Every message names the file.
#[derive(Debug, thiserror::Error)]
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
pub fn load(path: &Path) -> Result<ResultSet, ResultsError> {
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
        add_file(&mut set, path, file, true);
    }
    warn_duplicates(&mut set);
    Ok(set)
}

/// A parsed checkpoint file, before record validation.
struct CheckpointFile {
    records: Vec<Value>,
    merged: bool,
    entry_status: Option<String>,
    progress: Option<Vec<Value>>,
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
    let bytes = match fs::read(path) {
        Ok(b) => b,
        Err(source) => {
            return Parsed::Broken(ResultsError::Io {
                path: path.to_path_buf(),
                source,
            })
        }
    };
    let value: Value = match serde_json::from_slice(&bytes) {
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
        Some(Value::Array(a)) => a,
        Some(v) => return Parsed::Broken(format("_checkpoint.records", expected("an array", &v))),
    };
    let progress = match checkpoint.remove("progress") {
        Some(Value::Array(a)) => Some(a),
        _ => None,
    };
    let entry_status = top
        .get("entry_status")
        .and_then(Value::as_str)
        .map(String::from);
    Parsed::Checkpoint(CheckpointFile {
        records,
        merged: top.contains_key("driving score"),
        entry_status,
        progress,
        top,
    })
}

/// serde_json appends " at line L column C"; the error variants carry those separately.
fn strip_position(msg: &str) -> String {
    match msg.rfind(" at line ") {
        Some(i) => msg[..i].to_string(),
        None => msg.to_string(),
    }
}

fn add_file(set: &mut ResultSet, path: &Path, file: CheckpointFile, read_totals: bool) {
    let n = file.records.len();
    let progress_text = file.progress.as_ref().map(|p| {
        let parts: Vec<String> = p.iter().map(Value::to_string).collect();
        format!("[{}]", parts.join(", "))
    });
    let progress_pair = file.progress.as_ref().and_then(|p| match p.as_slice() {
        [a, b] => Some((a.as_u64()?, b.as_u64()?)),
        _ => None,
    });
    if n == 0 {
        let mut msg = format!("{}: no records", path.display());
        let mut details = Vec::new();
        if let Some(s) = &file.entry_status {
            details.push(format!("entry_status {s}"));
        }
        if let Some(p) = &progress_text {
            details.push(format!("progress {p}"));
        }
        if !details.is_empty() {
            let _ = write!(msg, " ({})", details.join(", "));
        }
        let unfinished = file
            .entry_status
            .as_deref()
            .is_some_and(|s| s != "Finished")
            || progress_pair.is_some_and(|(i, total)| i < total);
        if unfinished {
            msg.push_str(": the run crashed before any route finished");
        }
        set.warnings.push(msg);
    } else if let Some((_, total)) = progress_pair {
        if (n as u64) < total {
            set.warnings.push(format!(
                "{}: progress {} but only {n} of {total} routes recorded: the run did not finish",
                path.display(),
                progress_text.as_deref().unwrap_or("?"),
            ));
        }
    }
    if file.merged && read_totals {
        match merged_totals(&file.top, path) {
            Ok(t) => set.merged_totals.push(t),
            Err(reason) => set.warnings.push(format!(
                "{}: stored totals ignored: {reason}",
                path.display()
            )),
        }
    }
    for (index, value) in file.records.iter().enumerate() {
        let entry = Record::from_value(value);
        if let Ok(r) = &entry {
            let known = matches!(r.status.as_str(), "Completed" | "Perfect" | "Failed")
                || r.status.starts_with("Failed - ");
            if !known {
                set.warnings.push(format!(
                    "{}: record {index} ({}): unknown status {:?} (counted as not successful)",
                    path.display(),
                    r.route_id,
                    r.status
                ));
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
    let mut files = Vec::new();
    let mut visited = HashSet::new();
    if let Ok(canon) = fs::canonicalize(root) {
        visited.insert(canon);
    }
    let entries = fs::read_dir(root).map_err(|source| ResultsError::Io {
        path: root.to_path_buf(),
        source,
    })?;
    collect_json(entries, root, &mut files, &mut visited, &mut set.warnings);
    files.sort();

    let mut raw = Vec::new();
    let mut merged = Vec::new();
    for path in files {
        match parse_file(&path) {
            Parsed::Checkpoint(f) if f.merged => merged.push((path, f)),
            Parsed::Checkpoint(f) => raw.push((path, f)),
            Parsed::NotCheckpoint(_) => {}
            Parsed::Broken(e) => {
                let reason = e.to_string();
                set.warnings
                    .push(format!("skipped unreadable results file: {reason}"));
                set.broken_files.push((path, reason));
            }
        }
    }
    if raw.is_empty() && merged.is_empty() && set.broken_files.is_empty() {
        return Err(ResultsError::NoResults {
            path: root.to_path_buf(),
        });
    }
    if raw.is_empty() {
        for (path, f) in merged {
            add_file(set, &path, f, true);
        }
    } else {
        for (path, _) in &merged {
            set.warnings.push(format!(
                "{}: skipped: a Bench2Drive merged file (has \"driving score\") beside {} raw \
                 evaluator file(s); reading both would count its routes twice",
                path.display(),
                raw.len()
            ));
        }
        for (path, f) in raw {
            add_file(set, &path, f, false);
        }
    }
    Ok(())
}

fn collect_json(
    entries: fs::ReadDir,
    dir: &Path,
    files: &mut Vec<PathBuf>,
    visited: &mut HashSet<PathBuf>,
    warnings: &mut Vec<String>,
) {
    for entry in entries {
        let entry = match entry {
            Ok(e) => e,
            Err(e) => {
                warnings.push(format!("{}: cannot list: {e}", dir.display()));
                continue;
            }
        };
        let path = entry.path();
        // follows symlinks; a dangling link is reported and skipped
        let meta = match fs::metadata(&path) {
            Ok(m) => m,
            Err(e) => {
                warnings.push(format!("{}: cannot read: {e}", path.display()));
                continue;
            }
        };
        if meta.is_dir() {
            let canon = fs::canonicalize(&path).unwrap_or_else(|_| path.clone());
            if !visited.insert(canon) {
                continue; // a symlink loop or a second link to a folder already read
            }
            match fs::read_dir(&path) {
                Ok(sub) => collect_json(sub, &path, files, visited, warnings),
                Err(e) => warnings.push(format!("{}: cannot list: {e}", path.display())),
            }
        } else if meta.is_file() {
            let name = entry.file_name();
            let name = name.to_string_lossy();
            let is_json = path.extension().is_some_and(|e| e == "json");
            if is_json && name != "metric_info.json" && name != "infractions.json" {
                files.push(path);
            }
        }
    }
}

fn warn_duplicates(set: &mut ResultSet) {
    let mut first: HashMap<&str, &LoadedRecord> = HashMap::new();
    let mut warnings = Vec::new();
    for lr in &set.records {
        let id = match &lr.entry {
            Ok(r) => Some(r.route_id.as_str()),
            Err(e) => e.route_id.as_deref(),
        };
        let Some(id) = id else { continue };
        match first.get(id) {
            None => {
                first.insert(id, lr);
            }
            Some(prev) => warnings.push(format!(
                "duplicate route id {id}: record {} of {} and record {} of {} (both kept as \
                 separate routes)",
                prev.index,
                prev.source.display(),
                lr.index,
                lr.source.display()
            )),
        }
    }
    set.warnings.extend(warnings);
}

fn parse_infractions(m: &Map<String, Value>) -> Result<Infractions, String> {
    let mut inf = Infractions::default();
    for (name, v) in m {
        let field = format!("infractions.{name}");
        let Value::Array(items) = v else {
            return Err(wrong(&field, "an array of strings", v));
        };
        let mut entries = Vec::with_capacity(items.len());
        for (i, item) in items.iter().enumerate() {
            match item {
                Value::String(s) => entries.push(s.clone()),
                other => return Err(wrong(&format!("{field}[{i}]"), "a string", other)),
            }
        }
        inf.push_list(name.clone(), entries);
    }
    Ok(inf)
}

fn number_to_id(n: &serde_json::Number) -> String {
    if let Some(u) = n.as_u64() {
        return u.to_string();
    }
    if let Some(i) = n.as_i64() {
        return i.to_string();
    }
    match n.as_f64() {
        Some(f) if f.fract() == 0.0 && f.abs() < 1e15 => format!("{f:.0}"),
        _ => n.to_string(),
    }
}

fn kind(v: &Value) -> &'static str {
    match v {
        Value::Null => "null",
        Value::Bool(_) => "boolean",
        Value::Number(_) => "number",
        Value::String(_) => "string",
        Value::Array(_) => "array",
        Value::Object(_) => "object",
    }
}

fn expected(what: &str, got: &Value) -> String {
    format!("expected {what}, got {}", kind(got))
}

fn missing(field: &str) -> String {
    format!("field {field}: missing")
}

fn wrong(field: &str, what: &str, got: &Value) -> String {
    format!("field {field}: {}", expected(what, got))
}

fn req_str(m: &Map<String, Value>, key: &str, field: &str) -> Result<String, String> {
    match m.get(key) {
        None => Err(missing(field)),
        Some(Value::String(s)) => Ok(s.clone()),
        Some(v) => Err(wrong(field, "a string", v)),
    }
}

fn opt_str(m: &Map<String, Value>, key: &str, field: &str) -> Result<Option<String>, String> {
    match m.get(key) {
        None | Some(Value::Null) => Ok(None),
        Some(Value::String(s)) => Ok(Some(s.clone())),
        Some(v) => Err(wrong(field, "a string", v)),
    }
}

fn req_num(m: &Map<String, Value>, key: &str, field: &str) -> Result<f64, String> {
    match m.get(key) {
        None => Err(missing(field)),
        Some(v) => v.as_f64().ok_or_else(|| wrong(field, "a number", v)),
    }
}

fn opt_num(m: &Map<String, Value>, key: &str, field: &str) -> Result<Option<f64>, String> {
    match m.get(key) {
        None | Some(Value::Null) => Ok(None),
        Some(v) => v
            .as_f64()
            .map(Some)
            .ok_or_else(|| wrong(field, "a number", v)),
    }
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

    fn reason_of(v: &Value) -> String {
        Record::from_value(v).expect_err("must be invalid").reason
    }

    #[test]
    fn valid_record_fields() {
        let r = Record::from_value(&good()).unwrap();
        assert_eq!(r.route_id, "RouteScenario_24206_rep3");
        assert_eq!(r.xml_id(), Some("24206"));
        assert_eq!(r.scenario_type(), "ConstructionObstacle");
        assert_eq!(r.weather_id.as_deref(), Some("7"));
        assert_eq!(r.town_name.as_deref(), Some("Town12"));
        assert_eq!(r.score_route, 100.0);
        assert_eq!(r.meta.route_length, Some(102.063));
        assert_eq!(r.meta.duration_system, None);
        assert_eq!(r.infractions.list("min_speed_infractions").len(), 1);
        assert!(r.infractions.list("collisions_vehicle").is_empty());
        assert!(r.infractions.list("no_such_list").is_empty());
        assert!(r.is_success());
    }

    #[test]
    fn weather_id_numbers_and_null() {
        let mut v = good();
        v["weather_id"] = json!(23);
        assert_eq!(
            Record::from_value(&v).unwrap().weather_id.as_deref(),
            Some("23")
        );
        v["weather_id"] = json!(5.0);
        assert_eq!(
            Record::from_value(&v).unwrap().weather_id.as_deref(),
            Some("5")
        );
        v["weather_id"] = Value::Null;
        assert_eq!(Record::from_value(&v).unwrap().weather_id, None);
        v["weather_id"] = json!([1]);
        assert_eq!(
            reason_of(&v),
            "field weather_id: expected a string or number, got array"
        );
    }

    #[test]
    fn save_name_may_be_missing() {
        let mut v = good();
        v.as_object_mut().unwrap().remove("save_name");
        v.as_object_mut().unwrap().remove("meta");
        let r = Record::from_value(&v).unwrap();
        assert_eq!(r.save_name, None);
        assert_eq!(r.meta, Meta::default());
    }

    #[test]
    fn invalid_records_name_the_field() {
        let mut v = good();
        v["scores"]["score_route"] = json!("100");
        let e = Record::from_value(&v).unwrap_err();
        assert_eq!(e.route_id.as_deref(), Some("RouteScenario_24206_rep3"));
        assert_eq!(
            e.reason,
            "field scores.score_route: expected a number, got string"
        );

        let mut v = good();
        v["scores"].as_object_mut().unwrap().remove("score_penalty");
        assert_eq!(reason_of(&v), "field scores.score_penalty: missing");

        let mut v = good();
        v["scores"]["score_composed"] = Value::Null;
        assert_eq!(
            reason_of(&v),
            "field scores.score_composed: expected a number, got null"
        );

        let mut v = good();
        v.as_object_mut().unwrap().remove("route_id");
        let e = Record::from_value(&v).unwrap_err();
        assert_eq!(e.route_id, None);
        assert_eq!(e.reason, "field route_id: missing");

        let mut v = good();
        v["status"] = json!(1);
        assert_eq!(reason_of(&v), "field status: expected a string, got number");

        let mut v = good();
        v["infractions"] = json!([]);
        assert_eq!(
            reason_of(&v),
            "field infractions: expected an object, got array"
        );

        let mut v = good();
        v["infractions"]["red_light"] = json!("x");
        assert_eq!(
            reason_of(&v),
            "field infractions.red_light: expected an array of strings, got string"
        );

        let mut v = good();
        v["infractions"]["red_light"] = json!(["a", 3]);
        assert_eq!(
            reason_of(&v),
            "field infractions.red_light[1]: expected a string, got number"
        );

        let mut v = good();
        v["meta"]["route_length"] = json!("far");
        assert_eq!(
            reason_of(&v),
            "field meta.route_length: expected a number, got string"
        );

        assert_eq!(
            reason_of(&json!(3)),
            "record: expected an object, got number"
        );
    }

    #[test]
    fn success_rule() {
        let mut v = good();
        v["status"] = json!("Perfect");
        assert!(Record::from_value(&v).unwrap().is_success());
        v["status"] = json!("Failed - TickRuntime");
        assert!(!Record::from_value(&v).unwrap().is_success());
        let mut v = good();
        v["infractions"]["route_timeout"] = json!(["Route timeout."]);
        assert!(!Record::from_value(&v).unwrap().is_success());
        // an unknown extra list also breaks a success
        let mut v = good();
        v["infractions"]["collisions_ufo"] = json!(["x"]);
        let r = Record::from_value(&v).unwrap();
        assert!(!r.is_success());
        let unknown: Vec<_> = r.infractions.unknown().collect();
        assert_eq!(unknown, vec![("collisions_ufo", &["x".to_string()][..])]);
    }

    #[test]
    fn infractions_keep_unknown_order() {
        let inf = Infractions::from_lists([
            ("zeta", vec!["1".to_string()]),
            ("red_light", vec!["r".to_string()]),
            ("alpha", vec![]),
        ]);
        let names: Vec<_> = inf.unknown().map(|(n, _)| n).collect();
        assert_eq!(names, ["zeta", "alpha"]);
        assert_eq!(inf.list("red_light"), ["r".to_string()]);
        assert_eq!(inf.list("zeta"), ["1".to_string()]);
        assert_eq!(inf.all().count(), 14);
        assert!(!inf.clean_except_min_speed());
    }

    #[test]
    fn ids_and_types() {
        let mut r = Record::from_value(&good()).unwrap();
        r.route_id = "Route_7".into();
        assert_eq!(r.xml_id(), None);
        r.route_id = "RouteScenario_12_repx".into();
        assert_eq!(r.xml_id(), None);
        r.scenario_name = "Accident".into();
        assert_eq!(r.scenario_type(), "Accident");
        r.scenario_name = "Parking_Cut_In_2".into();
        assert_eq!(r.scenario_type(), "Parking_Cut_In");
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
        let e = load(&p).unwrap_err().to_string();
        assert!(e.contains("trunc.json"), "{e}");
        assert!(
            e.contains("truncated JSON") && e.contains("line 1, column 29"),
            "{e}"
        );

        let p = write(dir.path(), "bad.json", "{\"_checkpoint\": x}");
        let e = load(&p).unwrap_err().to_string();
        assert!(
            e.contains("bad.json: invalid JSON at line 1, column 17"),
            "{e}"
        );

        let p = write(dir.path(), "nock.json", "{\"records\": []}");
        let e = load(&p).unwrap_err().to_string();
        assert!(e.ends_with("nock.json: field _checkpoint: missing"), "{e}");

        let p = write(
            dir.path(),
            "norec.json",
            "{\"_checkpoint\": {\"records\": {}}}",
        );
        let e = load(&p).unwrap_err().to_string();
        assert!(
            e.ends_with("norec.json: field _checkpoint.records: expected an array, got object"),
            "{e}"
        );

        let e = load(&dir.path().join("absent.json"))
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
        let set = load(&p).unwrap();
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
        // records 0 and 1 share a route id
        assert_eq!(set.warnings.len(), 1, "{:?}", set.warnings);
        assert!(set.warnings[0].starts_with("duplicate route id RouteScenario_24206_rep3"));
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
        let set = load(&p).unwrap();
        assert_eq!(set.records.len(), 1);
        assert!(set
            .warnings
            .iter()
            .any(|w| w.contains("unknown status \"Exploded\"")));
        assert!(set
            .warnings
            .iter()
            .any(|w| w.contains("only 1 of 4 routes")));
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
        let e = load(dir.path()).unwrap_err();
        assert!(matches!(e, ResultsError::NoResults { .. }), "{e}");
    }
}
