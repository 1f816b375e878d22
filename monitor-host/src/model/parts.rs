//! The parts of a merged report (docs/SCORE.md §13.2), as its `inputs.parts` lists them;
//! [`crate::merge`] fills them.

use std::path::PathBuf;

use serde::{Deserialize, Serialize};
use serde_json::Value;

/// One part of a merged report, as its `inputs.parts` lists it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PartInputs {
    /// The part's file, as given.
    pub file: PathBuf,
    /// sha256 of the part's bytes.
    pub sha256: String,
    /// The `sds` version that scored the part (null for a report without provenance).
    pub sds_version: Option<String>,
    /// The part's own `inputs`, as it wrote them.
    pub inputs: Value,
}
