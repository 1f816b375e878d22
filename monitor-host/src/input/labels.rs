//! Label maps for the breakdown table (`SDS-SPEC.md` v1.2 §8.3): scenario type → family, or
//! weather id → label. A JSON object (`{"7": "ClearNoon"}`), or CSV / TSV lines `key,label`
//! (`#` starts a comment line; cells are trimmed; quoted cells may hold commas).
//!
//! ```
//! use monitor_host::input::labels::parse_labels;
//! let m = parse_labels("# type,family\nAccident, obstacles\n\"Hazard\",\"obstacles, static\"\n", "f.csv")?;
//! assert_eq!(m["Accident"], "obstacles");
//! assert_eq!(m["Hazard"], "obstacles, static");
//! let m = parse_labels(r#"{"7": "ClearNoon", "8": 3}"#, "w.json")?;
//! assert_eq!((m["7"].as_str(), m["8"].as_str()), ("ClearNoon", "3"));
//! # Ok::<(), monitor_host::input::labels::LabelsError>(())
//! ```

use std::path::{Path, PathBuf};

use crate::aggregate::groups::Labels;

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
    /// A JSON label file that is not an object.
    #[error("{file}: not a JSON object of labels: {message}")]
    Json {
        /// The file.
        file: String,
        /// The parser's message.
        message: String,
    },
    /// A key given twice (which label is meant is unknown).
    #[error("{file}: key {key:?} is given twice")]
    Duplicate {
        /// The file.
        file: String,
        /// The key.
        key: String,
    },
    /// A CSV line without a label.
    #[error("{file}:{line}: expected `key,label`")]
    Line {
        /// The file.
        file: String,
        /// 1-based line.
        line: u64,
    },
}

/// Reads a label file (see [`parse_labels`]).
///
/// # Errors
/// [`LabelsError`], naming the file.
pub fn read_labels(path: &Path) -> Result<Labels, LabelsError> {
    let text = crate::input::read::read_input_text(path, crate::input::read::FileKind::Labels)
        .map_err(|source| LabelsError::Io {
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
    if text.trim_start().starts_with('{') {
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
        return Ok(map
            .into_iter()
            .map(|(k, v)| {
                let label = v.as_str().map_or_else(|| v.to_string(), str::to_string);
                (k, label)
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
        let label = label.join(if delimiter == b'\t' { "\t" } else { "," });
        if map.insert(key.to_string(), label).is_some() {
            return Err(LabelsError::Duplicate {
                file: file.into(),
                key: key.to_string(),
            });
        }
    }
    Ok(map)
}
