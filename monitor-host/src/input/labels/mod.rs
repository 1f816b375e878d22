//! Label maps for the breakdown table (docs/SCORE.md §10.2): scenario type → family, or
//! weather id → label; a key may have several labels (the route then counts in each group).
//! A JSON object whose values are a label or a list of labels (`{"7": "ClearNoon",
//! "Accident": ["obstacles", "static"]}`), CSV / TSV lines `key,label` (`#` starts a comment
//! line; cells are trimmed; quoted cells may hold commas; a key on several lines has several
//! labels), or Bench2Drive's `weather.xml` (each weather named after the CARLA preset it is,
//! else by its id).
//!
//! ```
//! use monitor_host::input::labels::parse_labels;
//! let m = parse_labels("# type,family\nAccident, obstacles\n\"Hazard\",\"obstacles, static\"\nAccident,rare\n", "f.csv")?;
//! assert_eq!(m["Accident"], ["obstacles", "rare"]);
//! assert_eq!(m["Hazard"], ["obstacles, static"]);
//! let m = parse_labels(r#"{"7": "ClearNoon", "8": 3, "9": ["a", "b"]}"#, "w.json")?;
//! assert_eq!((m["7"][0].as_str(), m["8"][0].as_str()), ("ClearNoon", "3"));
//! assert_eq!(m["9"], ["a", "b"]);
//! # Ok::<(), monitor_host::input::labels::LabelsError>(())
//! ```

use std::path::{Path, PathBuf};

use std::collections::BTreeMap;

pub mod carla_weather;
mod weather_xml;

/// What `--families safe2drive` means, said instead of reading a file of that name: the
/// Safe2Drive paper groups its routes into three families but names the scenario type of one
/// of them only, and a family map is keyed by scenario type, so the project ships no built-in
/// map (a guessed one would put routes in the wrong rows of a published table).
pub const SAFE2DRIVE_FAMILIES: &str = "families takes a file that maps scenario types to \
    family labels (`type,family` lines, or a JSON object). The Safe2Drive paper groups its 100 \
    routes into three families: work zones (75 routes, its `StaticWorkzoneRoute` scenario), \
    pedestrian jaywalking (10) and occluded vulnerable road users (15: a worker hidden by a \
    construction vehicle, a child hidden by a bus, blind corners and buildings). It names the \
    scenario type of the work-zone routes only, so there is no built-in `safe2drive` map: write \
    one line per scenario type of your run, e.g. `StaticWorkzoneRoute,work zone` (the types are \
    the record's `scenario_name` without its `_N` suffix; `group_by = scenario` lists them)";

/// Whether `--families PATH` names the Safe2Drive paper rather than a file: no file is there and
/// its name is `safe2drive` (any case, with or without `.csv` / `.json`).
///
/// ```
/// use monitor_host::input::labels::names_safe2drive;
/// assert!(names_safe2drive(std::path::Path::new("Safe2Drive")));
/// assert!(!names_safe2drive(std::path::Path::new("families.csv")));
/// ```
pub fn names_safe2drive(path: &Path) -> bool {
    let stem = path.file_name().and_then(|n| n.to_str()).map(|n| {
        n.trim_end_matches(".csv")
            .trim_end_matches(".json")
            .to_ascii_lowercase()
    });
    stem.as_deref() == Some("safe2drive") && !path.exists()
}

/// Labels of scenario types (families), weather ids or route ids, read by
/// [`read_labels`]; a key may have several labels.
pub type Labels = BTreeMap<String, Vec<String>>;

/// Why a label file cannot be used; names the file (and line).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum LabelsError {
    /// The file cannot be read.
    #[error("cannot read {}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The OS error.
        #[source]
        source: std::io::Error,
    },
    /// A key given twice in a JSON label file (which label is meant is unknown; a key with
    /// several labels takes a JSON array).
    #[error("{file}: key {key:?} is given twice")]
    Duplicate {
        /// The file.
        file: String,
        /// The key.
        key: String,
    },
    /// A JSON label file that is not an object.
    #[error("{file}: not a JSON object of labels: {message}")]
    Json {
        /// The file.
        file: String,
        /// The parser's message.
        message: String,
    },
    /// A CSV line without a label.
    #[error("{file}:{line}: expected `key,label`")]
    Line {
        /// The file.
        file: String,
        /// 1-based line.
        line: u64,
    },
    /// A CSV line whose key or label is empty, or whose quoted cell runs over several lines
    /// (an unclosed quote would otherwise swallow the rest of the file).
    #[error("{file}:{line}: {problem}")]
    Cell {
        /// The file.
        file: String,
        /// 1-based line.
        line: u64,
        /// What is wrong.
        problem: String,
    },
    /// A JSON label that is not a non-empty string or a number (or a list of them).
    #[error("{file}: key {key:?}: {problem}")]
    Value {
        /// The file.
        file: String,
        /// The key.
        key: String,
        /// What is wrong.
        problem: String,
    },
    /// A `weather.xml` that cannot be read.
    #[error("{file}: {message}")]
    Xml {
        /// The file.
        file: String,
        /// What is wrong.
        message: String,
    },
    /// `--families safe2drive` (no such file): the name of the Safe2Drive paper, whose families
    /// cannot be a built-in map (see [`SAFE2DRIVE_FAMILIES`]).
    #[error("families {}: no such file. {SAFE2DRIVE_FAMILIES}", path.display())]
    Safe2DriveFamilies {
        /// The name given.
        path: PathBuf,
    },
    /// No key of the file matches any route (a label file for something else?).
    #[error(
        "{}: none of its {keys} key(s) matches a route's {what} (the routes have e.g. {}); \
         is it the right file for {option}?",
        file.display(), examples.join(", ")
    )]
    NoMatch {
        /// The file.
        file: PathBuf,
        /// Keys in the file.
        keys: usize,
        /// What the keys are (`scenario type`, `weather id`).
        what: &'static str,
        /// The option (`--families`, `--weathers`).
        option: &'static str,
        /// Some keys of the routes.
        examples: Vec<String>,
    },
}

/// Checks a label file against the routes' keys: an error when no key matches, else the keys
/// without a label (sorted, each once).
///
/// ```
/// use monitor_host::input::labels::{check_coverage, parse_labels};
/// use std::path::Path;
/// let labels = parse_labels("Accident,obstacles\n", "f.csv")?;
/// let f = Path::new("f.csv");
/// let missing = check_coverage(&labels, ["Accident", "HardBreakRoute"], f, "scenario type", "--families")?;
/// assert_eq!(missing, ["HardBreakRoute"]);
/// assert!(check_coverage(&labels, ["HardBreakRoute"], f, "scenario type", "--families").is_err());
/// # Ok::<(), monitor_host::LabelsError>(())
/// ```
///
/// # Errors
/// [`LabelsError::NoMatch`].
pub fn check_coverage<'a>(
    labels: &Labels,
    keys: impl IntoIterator<Item = &'a str>,
    file: &Path,
    what: &'static str,
    option: &'static str,
) -> Result<Vec<String>, LabelsError> {
    let keys: std::collections::BTreeSet<&str> = keys.into_iter().collect();
    if !keys.is_empty() && !keys.iter().any(|k| labels.contains_key(*k)) {
        return Err(LabelsError::NoMatch {
            file: file.to_path_buf(),
            keys: labels.len(),
            what,
            option,
            examples: keys.iter().take(3).map(|k| k.to_string()).collect(),
        });
    }
    Ok(keys
        .into_iter()
        .filter(|k| !labels.contains_key(*k))
        .map(String::from)
        .collect())
}

/// Reads a label file (see [`parse_labels`]).
///
/// # Errors
/// [`LabelsError`], naming the file.
pub fn read_labels(path: &Path) -> Result<Labels, LabelsError> {
    let kind = crate::input::read::FileKind::Labels;
    let text =
        crate::input::read::read_input_text(path, kind).map_err(|source| LabelsError::Io {
            path: path.to_path_buf(),
            source,
        })?;
    parse_labels(&text, &path.display().to_string())
}

/// Parses the text of a label file; `file` names it in errors.
///
/// # Errors
/// [`LabelsError::Json`] or [`LabelsError::Line`].
pub fn parse_labels(text: &str, file: &str) -> Result<Labels, LabelsError> {
    // A byte order mark is not part of the text (a JSON file saved with one is still JSON).
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let start = text.trim_start();
    if start.starts_with('<') {
        return weather_xml::parse(text, file);
    }
    if start.starts_with('{') {
        if let Ok(Some(key)) = crate::input::json_keys::first_duplicate_key(text.as_bytes()) {
            return Err(LabelsError::Duplicate {
                file: file.into(),
                key,
            });
        }
        let map: std::collections::BTreeMap<String, serde_json::Value> = serde_json::from_str(text)
            .map_err(|e| LabelsError::Json {
                file: file.into(),
                message: e.to_string(),
            })?;
        let bad = |k: &str, problem: String| LabelsError::Value {
            file: file.into(),
            key: k.to_string(),
            problem,
        };
        // A label is a non-empty string or a number; null, true, objects and nested lists
        // are mistakes, not labels.
        let one = |k: &str, v: &serde_json::Value| match v {
            serde_json::Value::String(s) if s.trim().is_empty() => {
                Err(bad(k, "an empty label".into()))
            }
            serde_json::Value::String(s) => Ok(s.clone()),
            serde_json::Value::Number(n) => Ok(n.to_string()),
            other => Err(bad(
                k,
                format!(
                    "{other} is not a label (a label is a string or a number, or a list of them)"
                ),
            )),
        };
        let mut out = Labels::new();
        for (k, v) in map {
            let labels = match &v {
                serde_json::Value::Array(a) if a.is_empty() => {
                    return Err(bad(&k, "an empty list: no label".into()))
                }
                serde_json::Value::Array(a) => {
                    a.iter().map(|x| one(&k, x)).collect::<Result<_, _>>()?
                }
                v => vec![one(&k, v)?],
            };
            out.insert(k, labels);
        }
        return Ok(out);
    }
    // Tab-separated when the file has tabs and no comma.
    let delimiter = if text.contains('\t') && !text.contains(',') {
        b'\t'
    } else {
        b','
    };
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .comment(Some(b'#'))
        .trim(csv::Trim::All)
        .delimiter(delimiter)
        .from_reader(text.as_bytes());
    let mut map = Labels::new();
    for record in reader.records() {
        let bad = |line| LabelsError::Line {
            file: file.into(),
            line,
        };
        let record = record.map_err(|e| bad(e.position().map_or(0, |p| p.line())))?;
        let line = record.position().map_or(0, |p| p.line());
        if record.iter().all(str::is_empty) {
            continue;
        }
        let mut cells = record.iter();
        let (Some(key), Some(_)) = (cells.next(), record.get(1)) else {
            return Err(bad(line));
        };
        let cell_error = |problem: &str| LabelsError::Cell {
            file: file.into(),
            line,
            problem: problem.into(),
        };
        if record.iter().any(|c| c.contains(['\n', '\r'])) {
            return Err(cell_error(
                "a quoted cell runs over several lines (an unclosed `\"`?)",
            ));
        }
        // An unquoted label may itself hold the delimiter: keep the rest of the line.
        let label: Vec<&str> = record.iter().skip(1).collect();
        let label = label.join(if delimiter == b'\t' { "\t" } else { "," });
        if key.is_empty() {
            return Err(cell_error("an empty key"));
        }
        if label.trim_matches([',', '\t', ' ']).is_empty() {
            return Err(cell_error(&format!("key {key:?} has an empty label")));
        }
        map.entry(key.to_string()).or_default().push(label);
    }
    Ok(map)
}
