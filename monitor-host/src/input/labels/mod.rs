//! Label maps for the breakdown table (`SDS-SPEC.md` v1.2 §8.3): scenario type → family, or
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
    /// A `weather.xml` that cannot be read.
    #[error("{file}: {message}")]
    Xml {
        /// The file.
        file: String,
        /// What is wrong.
        message: String,
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
        let one = |v: &serde_json::Value| v.as_str().map_or_else(|| v.to_string(), str::to_string);
        return Ok(map
            .into_iter()
            .map(|(k, v)| {
                let labels = match &v {
                    serde_json::Value::Array(a) => a.iter().map(one).collect(),
                    v => vec![one(v)],
                };
                (k, labels)
            })
            .collect());
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
        // An unquoted label may itself hold the delimiter: keep the rest of the line.
        let label: Vec<&str> = record.iter().skip(1).collect();
        map.entry(key.to_string())
            .or_default()
            .push(label.join(if delimiter == b'\t' { "\t" } else { "," }));
    }
    Ok(map)
}
