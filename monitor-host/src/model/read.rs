//! A report read back by the types that write it (docs/USAGE.md "Reading a report back"):
//! [`Report::read`] parses an `sds score` or `sds merge` JSON report into the very [`Report`]
//! that wrote it, so a field added to a report type reads back with no second reader to keep
//! in step. An error names the file, the JSON path of the field (`routes[3].comfort.score`),
//! what was expected and what was found, and, for a report another `sds` version wrote, both
//! versions.

use std::io::Read;
use std::path::{Path, PathBuf};

use crate::input::read::{read_input, FileKind};
use crate::model::report::{Report, SCHEMA};
use crate::provenance::SDS_VERSION;

/// Why a report cannot be read back.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ReadError {
    /// The file cannot be read.
    #[error("{}: cannot read: {source}", file.display())]
    Io {
        /// The file.
        file: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The file is not a report this version reads.
    #[error(
        "{}: not an sds report ({source}); a report is the JSON file sds score or sds merge \
         writes (--format json)",
        file.display()
    )]
    Format {
        /// The file.
        file: PathBuf,
        /// What is wrong, and where.
        source: FormatError,
    },
}

/// What is wrong with a report's JSON: the field's JSON path and the problem.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{}{why}{}", at(path), version_note(written_by.as_deref()))]
pub struct FormatError {
    /// The field's JSON path (`routes[3].comfort.score`); empty for the whole file.
    pub path: String,
    /// What was expected and found (`expected a number, got string "high"`).
    pub why: String,
    /// The `sds` version that wrote the report (`inputs.provenance.sds_version`), when it can
    /// be read and is not this one.
    pub written_by: Option<String>,
}

/// `path: `, or nothing for the whole file.
fn at(path: &str) -> String {
    if path.is_empty() {
        String::new()
    } else {
        format!("{path}: ")
    }
}

fn version_note(written_by: Option<&str>) -> String {
    written_by.map_or_else(String::new, |v| {
        format!(
            " (written by sds {v}; this is sds {SDS_VERSION}, which reads the reports it \
             writes: score the run again with it)"
        )
    })
}

impl Report {
    /// Reads the JSON report in `file` (bounded, as every input: a FIFO or a device is refused).
    ///
    /// ```
    /// use monitor_host::{demo, report, score_run, Inputs, Report, Settings};
    /// let dir = tempfile::tempdir()?;
    /// let run = demo::write(dir.path())?;
    /// let inputs = Inputs { telemetry: Some(run.telemetry), ..Inputs::new([run.results]) };
    /// let written = score_run(&inputs, &Settings::default())?;
    /// let file = dir.path().join("report.json");
    /// std::fs::write(&file, report::json::json(&written)?)?;
    /// let read = Report::read(&file)?;
    /// assert_eq!(report::json::json(&read)?, report::json::json(&written)?);
    /// assert_eq!(read.summary, written.summary);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    ///
    /// # Errors
    /// [`ReadError::Io`] when it cannot be read, [`ReadError::Format`] naming the first field
    /// that is not what this version writes.
    pub fn read(file: &Path) -> Result<Report, ReadError> {
        let bytes = read_input(file, FileKind::Report).map_err(|source| ReadError::Io {
            file: file.to_path_buf(),
            source,
        })?;
        Report::from_json(&bytes).map_err(|source| ReadError::Format {
            file: file.to_path_buf(),
            source,
        })
    }

    /// Reads a JSON report from `reader` (to its end).
    ///
    /// # Errors
    /// As [`Report::from_json`]; a read error is a [`FormatError`] too.
    pub fn from_reader(mut reader: impl Read) -> Result<Report, FormatError> {
        let mut bytes = Vec::new();
        reader
            .read_to_end(&mut bytes)
            .map_err(|e| whole(format!("cannot read: {e}")))?;
        Report::from_json(&bytes)
    }

    /// Reads a JSON report from its bytes.
    ///
    /// ```
    /// use monitor_host::Report;
    /// let e = Report::from_json(br#"{"schema": "sds-compare/1"}"#).unwrap_err();
    /// assert_eq!(e.to_string(), "schema sds-compare/1, not sds-report/1");
    /// ```
    ///
    /// # Errors
    /// [`FormatError`]: not JSON, another schema, or the first field that is not what this
    /// version writes, with its JSON path.
    pub fn from_json(bytes: &[u8]) -> Result<Report, FormatError> {
        // One parse: a report that reads is of this schema (its `schema` field admits only
        // SCHEMA). Only on failure is the head looked at, so that another file says what it
        // is (not JSON, another schema) before a missed field is named.
        let mut de = serde_json::Deserializer::from_slice(bytes);
        let e = match serde_path_to_error::deserialize::<_, Report>(&mut de) {
            // Trailing bytes after the report: not JSON, said by the head's parse below.
            Ok(report) if de.end().is_ok() => return Ok(report),
            Ok(_) => None,
            Err(e) => Some(e),
        };
        schema_of(bytes)?;
        let Some(e) = e else {
            return Err(whole("not JSON: trailing characters".into()));
        };
        Err(FormatError {
            path: e.path().to_string(),
            why: plain(&e.inner().to_string()),
            written_by: written_by(bytes),
        })
    }
}

/// The head of a file that did not read as a report: not JSON, or no or another schema.
fn schema_of(bytes: &[u8]) -> Result<(), FormatError> {
    #[derive(serde::Deserialize)]
    struct Head {
        schema: Option<serde_json::Value>,
    }
    let head: Head = serde_json::from_slice(bytes).map_err(|e| whole(format!("not JSON: {e}")))?;
    match head.schema {
        Some(serde_json::Value::String(s)) if s == SCHEMA => Ok(()),
        Some(serde_json::Value::String(s)) => Err(whole(format!("schema {s}, not {SCHEMA}"))),
        _ => Err(whole(format!("no \"schema\": \"{SCHEMA}\""))),
    }
}

fn whole(why: String) -> FormatError {
    FormatError {
        path: String::new(),
        why,
        written_by: None,
    }
}

/// The version that wrote the report, when it is not this one.
fn written_by(bytes: &[u8]) -> Option<String> {
    #[derive(serde::Deserialize)]
    struct Provenance {
        sds_version: String,
    }
    #[derive(serde::Deserialize)]
    struct Inputs {
        provenance: Provenance,
    }
    #[derive(serde::Deserialize)]
    struct Head {
        inputs: Inputs,
    }
    let v = serde_json::from_slice::<Head>(bytes)
        .ok()?
        .inputs
        .provenance
        .sds_version;
    (v != SDS_VERSION).then_some(v)
}

/// serde's message in the report's words: `expected a number, got string "high"` for
/// `invalid type: string "high", expected f64`.
fn plain(message: &str) -> String {
    let words = |expected: &str| match expected {
        "f32" | "f64" => "a number".to_string(),
        "u8" | "u16" | "u32" | "u64" | "usize" => "a whole number".to_string(),
        "a boolean" => "true or false".to_string(),
        "a sequence" => "an array".to_string(),
        "a map" => "an object".to_string(),
        e => e.to_string(),
    };
    for prefix in ["invalid type: ", "invalid value: "] {
        if let Some((got, rest)) = message
            .strip_prefix(prefix)
            .and_then(|m| m.split_once(", expected "))
        {
            let (expected, place) = match rest.rsplit_once(" at line ") {
                Some((e, p)) => (e, format!(" (line {p})")),
                None => (rest, String::new()),
            };
            return format!("expected {}, got {got}{place}", words(expected));
        }
    }
    message.to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn serde_messages_read_in_the_reports_words() {
        assert_eq!(
            plain("invalid type: string \"high\", expected f64 at line 1 column 20"),
            "expected a number, got string \"high\" (line 1 column 20)"
        );
        assert_eq!(
            plain("invalid value: integer `-1`, expected u32"),
            "expected a whole number, got integer `-1`"
        );
        assert_eq!(plain("missing field `frames`"), "missing field `frames`");
    }

    /// One parse, the errors as when the head was parsed first: the file's kind before a
    /// missed field.
    #[test]
    fn a_file_that_is_not_a_report_says_what_it_is() {
        let said = |b: &[u8]| Report::from_json(b).unwrap_err().to_string();
        assert!(said(b"{\"schema\": ").starts_with("not JSON: "));
        assert!(said(b"{\"schema\": \"sds-report/1\"} x").starts_with("not JSON: trailing"));
        assert_eq!(said(br#"{"routes": 1}"#), "no \"schema\": \"sds-report/1\"");
        assert_eq!(
            said(br#"{"schema": "sds-compare/1", "routes": 1}"#),
            "schema sds-compare/1, not sds-report/1"
        );
        assert_eq!(
            said(br#"{"schema": "sds-report/1"}"#),
            ".: missing field `profile` at line 1 column 26"
        );
    }
}
