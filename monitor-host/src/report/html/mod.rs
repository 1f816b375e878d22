//! The report as one self-contained HTML page: the decomposition from DS to SDS and DS per
//! route as pictures, the headline tables, a sortable and filterable
//! route table, per route a drill-down (collision figures, comfort and lateral timelines,
//! warnings) and the run's warnings; and [`compare_page`], the comparison of runs (spec v1.3
//! docs/SCORE.md §10.3: tables, forest plot, per-route deltas, each run).
//!
//! Self-contained: the style sheet and the one script are inlined, the figures are inline SVG,
//! nothing is fetched (it opens from a mail attachment). The script only sorts, filters and
//! checks the page; every number is written by Rust. Deterministic: the same report gives the
//! same bytes.

mod compare;
mod page;
mod pictures;
mod routes;
pub mod seeds;
pub mod sweep;
mod timeline;

use crate::report::table::{self, TableOptions};
use crate::report::Report;

pub use compare::compare_page;
pub use page::{escape, live_page};

/// The whole report as an HTML page.
///
/// ```
/// use monitor_host::{demo, score_run, Inputs, Settings};
/// let dir = tempfile::tempdir()?;
/// let run = demo::write(dir.path())?;
/// let inputs = Inputs { telemetry: Some(run.telemetry), ..Inputs::new([run.results]) };
/// let report = score_run(&inputs, &Settings::default())?;
/// let html = monitor_host::report::html::page(&report, &Default::default(), "demo");
/// assert!(html.starts_with("<!DOCTYPE html>") && html.contains("id=\"routes\""));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn page(report: &Report, options: &TableOptions, name: &str) -> String {
    let mut body = String::new();
    page::heading(&mut body, report, name);
    pictures::pictures(&mut body, report);
    body.push_str("<h2 id=\"tables\">Headline tables</h2>\n");
    for g in table::report_tables(report, options) {
        page::grid(&mut body, &g);
    }
    routes::route_table(&mut body, report);
    routes::drill_downs(&mut body, report);
    page::warnings(&mut body, report);
    page::document(&format!("SDS report: {name}"), &body)
}
