//! Merging reports scored where the files are (`SDS-SPEC.md` v1.4 §13).

use serde::{Deserialize, Serialize};

/// One part of a merged report, as its `inputs.parts` lists it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PartInputs {
    /// The part's file, as given.
    pub file: std::path::PathBuf,
    /// sha256 of the part's bytes.
    pub sha256: String,
    /// The `sds` version that scored the part (null for a report without provenance).
    pub sds_version: Option<String>,
    /// The part's own `inputs`, as it wrote them.
    pub inputs: serde_json::Value,
}
