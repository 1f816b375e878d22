//! `sds.merge` (docs/SCORE.md §13.2): the library's [`MergeRequest`] over the parts' files, the
//! merged report converted to Python objects directly ([`crate::pyser`]), its warnings raised
//! as `sds.SdsWarning`.

use monitor_host::input::duplicates::DuplicatePolicy;
use monitor_host::{MergeRequest, NoProgress};
use pyo3::prelude::*;

use crate::errors::merge_error;
use crate::interrupt::with_signals;
use crate::options::{named, warn_report, Paths};
use crate::pyser::to_python;

/// Merges reports scored where the files are; returns the report of ``sds merge``.
///
/// Each part is the JSON report of ``sds score`` (or ``sds.score``'s dict written with
/// ``json.dump``) over one shard, all scored with the same settings and route XML. The merged
/// report equals ``sds.score`` over all the shards' files in every field but ``inputs`` (the
/// parts) and ``warnings`` (each part's, naming it); a merge of merges equals one merge. The
/// GIL is released while reading and merging; Ctrl-C raises ``KeyboardInterrupt``.
///
/// Args:
///     parts: The parts' JSON files, in input order.
///     duplicates: A route recorded in two parts: ``"error"`` (raise, naming both parts),
///         keep the ``"first"`` or ``"last"`` part's record, the ``"newest"`` (latest
///         ``save_name`` time stamp, which each row keeps), or score ``"all"``; the merged
///         ``config.duplicates`` states the rule applied.
///     host: Name this machine in ``inputs.provenance`` (``--set provenance.host=false``).
///
/// Returns:
///     The merged report.
///
/// Warns:
///     SdsWarning: Each of the merged report's ``warnings`` (each part's, naming it), at the
///         caller's line.
///
/// Raises:
///     RefusedError: A part is not an ``sds`` report, or was edited (a row out of range, its
///         arithmetic broken, rows that are not its route set), parts were scored with
///         different settings, route sets, route XML bytes, maps or label files, or a route is
///         recorded in two parts under ``duplicates="error"`` (an
///         :class:`InputError` and a :class:`ConfigError`).
///     IoError: A part cannot be read.
///     ConfigError: An unknown ``duplicates``.
///
/// Example:
///     >>> merged = sds.merge(["part0.json", "part1.json"])  # doctest: +SKIP
///     >>> merged["summary"]["driving_score"]  # doctest: +SKIP
#[pyfunction]
#[pyo3(signature = (parts, *, duplicates="error", host=true))]
pub fn merge<'py>(
    py: Python<'py>,
    parts: Paths,
    duplicates: &str,
    host: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let request = MergeRequest {
        duplicates: named(
            "duplicates",
            duplicates,
            DuplicatePolicy::from_name,
            DuplicatePolicy::choices,
        )?,
        host,
        ..MergeRequest::new(parts.into_vec())
    };
    // The parts are read on a worker thread while this one looks for signals: Ctrl-C raises
    // `KeyboardInterrupt` (`interrupt.rs`); each read is bounded, so the worker ends soon.
    let report = py
        .detach(|| with_signals(&NoProgress, |_| request.merge()))?
        .map_err(|e| merge_error(&e))?;
    let report = to_python(py, &report)?;
    warn_report(&report)?;
    Ok(report)
}
