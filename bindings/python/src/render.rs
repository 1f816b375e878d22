//! The pictures and the HTML page of a report already scored (for `sds.log`): the report's
//! JSON file read back by the library's merge reader ([`monitor_host::merge::merge`], one part:
//! the same report) and rendered as `sds score --format html` and `--figures` render it (the
//! library's one [`monitor_host::report::render::render`]).

use std::path::PathBuf;

use monitor_host::input::duplicates::DuplicatePolicy;
use monitor_host::report::render::{self as report_render, Format, RenderOptions};
use pyo3::prelude::*;

use crate::errors::InputError;

/// The HTML page (`report.html`) and the figures (`decomposition.svg` when the run has a
/// decomposition, `routes.svg`) of the `sds score` JSON report in `file`, by file name; `name`
/// is the run's name in the page's title. Raises `InputError` (or `IoError`) as `sds merge`
/// of that one file would.
#[pyfunction]
pub fn render(py: Python<'_>, file: PathBuf, name: &str) -> PyResult<Vec<(String, String)>> {
    let report = py
        .detach(|| monitor_host::merge::merge(&[file], DuplicatePolicy::All, false))
        .map_err(|e| InputError::new_err(monitor_host::error::message(&e)))?;
    let options = RenderOptions {
        name: name.to_string(),
        ..RenderOptions::default()
    };
    let page = report_render::render(&report, Format::Html, &options)
        .map_err(|e| InputError::new_err(e.to_string()))?;
    let mut out = vec![(
        "report.html".to_string(),
        String::from_utf8_lossy(&page).into_owned(),
    )];
    out.extend(
        report_render::figures(&report)
            .into_iter()
            .map(|(n, svg)| (n.to_string(), svg)),
    );
    Ok(out)
}
