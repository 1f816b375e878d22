//! The JSON rendering of the report (`SDS-SPEC.md` v1.2 §10): pretty-printed, keys in the
//! model's field order, one trailing newline.

use crate::model::report::Report;

/// The report as pretty-printed JSON with a trailing newline.
///
/// # Errors
/// Only if serialisation fails, which the report's types rule out.
pub fn json(report: &Report) -> Result<Vec<u8>, serde_json::Error> {
    let mut v = serde_json::to_vec_pretty(report)?;
    v.push(b'\n');
    Ok(v)
}
