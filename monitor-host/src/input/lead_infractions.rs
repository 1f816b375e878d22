//! LEAD's step-exact collision file, `infractions.json` beside `metric_info.json`
//! (docs/SCORE.md §6): the metric_info step of each infraction and its message.

use std::path::{Path, PathBuf};

/// Why an `infractions.json` cannot be used (the route is then aligned by position, with a
/// warning).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum LeadInfractionsError {
    /// The file cannot be read.
    #[error("cannot read {}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The OS error.
        #[source]
        source: std::io::Error,
    },
    /// The file does not have the expected shape (the parser's message, with line and column).
    #[error("invalid infractions.json: {0}")]
    Shape(String),
}

/// One entry of LEAD's `infractions.json`: the metric_info step of an infraction and its message
/// (the same text as the evaluator's infraction string).
#[derive(Debug, Clone, PartialEq, Eq, serde::Deserialize)]
pub struct StepInfraction {
    /// The step, in `metric_info.json`'s numbering.
    pub step: u64,
    /// The infraction message.
    pub message: String,
}

#[derive(serde::Deserialize)]
struct InfractionsFile {
    infractions: Vec<StepInfraction>,
}

/// Reads LEAD's `infractions.json` (`{"infractions": [{"step", "message", ...}], ...}`); other
/// keys of the file and of each entry are ignored.
///
/// # Errors
/// [`LeadInfractionsError::Io`] if unreadable; [`LeadInfractionsError::Shape`] (with line and column)
/// if the shape is wrong (e.g. an entry without an integer `step` or a string `message`).
pub fn read_lead_infractions(path: &Path) -> Result<Vec<StepInfraction>, LeadInfractionsError> {
    let bytes =
        crate::input::read::read_input_held(path, crate::input::read::FileKind::LeadInfractions)
            .map_err(|source| LeadInfractionsError::Io {
                path: path.to_path_buf(),
                source,
            })?;
    parse_lead_infractions(&bytes)
}

/// [`read_lead_infractions`] from memory.
///
/// ```
/// use monitor_host::input::lead_infractions::parse_lead_infractions;
/// let v = parse_lead_infractions(br#"{"infractions": [{"step": 813, "frame": 1626,
///     "message": "Agent collided against object with type=static.prop.constructioncone and id=7 at (x=1.0, y=2.0, z=0.0)",
///     "event_type": "COLLISION_STATIC"}], "other": 1}"#)?;
/// assert_eq!(v[0].step, 813);
/// # Ok::<(), monitor_host::input::lead_infractions::LeadInfractionsError>(())
/// ```
///
/// # Errors
/// As [`read_lead_infractions`].
pub fn parse_lead_infractions(bytes: &[u8]) -> Result<Vec<StepInfraction>, LeadInfractionsError> {
    serde_json::from_slice::<InfractionsFile>(bytes)
        .map(|f| f.infractions)
        .map_err(|e| LeadInfractionsError::Shape(e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn infractions_file() {
        let v = parse_lead_infractions(
            br#"{"infractions": [
                {"step": 10, "infraction": "COLLISION_VEHICLE", "frame": 20, "message": "a", "event_type": 1, "meters_travelled": 3.5},
                {"step": 12, "message": "b"}], "extra": {}}"#,
        )
        .unwrap();
        assert_eq!(
            v,
            vec![
                StepInfraction {
                    step: 10,
                    message: "a".into()
                },
                StepInfraction {
                    step: 12,
                    message: "b".into()
                }
            ]
        );
        let e = parse_lead_infractions(br#"{"infractions": [{"message": "a"}]}"#).unwrap_err();
        assert!(e.to_string().contains("missing field `step`"), "{e}");
        assert!(parse_lead_infractions(b"[]").is_err());
        let e = read_lead_infractions(Path::new("/nonexistent/infractions.json")).unwrap_err();
        assert!(e.to_string().starts_with("cannot read "), "{e}");
    }
}
