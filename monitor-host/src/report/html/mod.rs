//! The report as one self-contained HTML page: the decomposition from DS to SDS and DS per
//! route as pictures, the headline tables, a sortable and filterable
//! route table, per route a drill-down (collision figures, comfort and lateral timelines,
//! warnings) and the run's warnings; and [`compare_page`], runs side by side.
//!
//! Self-contained: the style sheet and the one script are inlined, the figures are inline SVG,
//! nothing is fetched (it opens from a mail attachment). The script only sorts, filters and
//! checks the page; every number is written by Rust. Deterministic: the same report gives the
//! same bytes.

mod page;
mod pictures;
mod routes;
mod timeline;

use crate::aggregate::compare::Comparison;
use crate::report::grid::Grid;
use crate::report::table::{self, TableOptions};
use crate::report::Report;

pub use page::escape;

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
        grid(&mut body, &g);
    }
    routes::route_table(&mut body, report);
    routes::drill_downs(&mut body, report);
    page::warnings(&mut body, report);
    page::document(&format!("SDS report: {name}"), &body)
}

/// Several runs side by side: the comparison's tables, then each run's headline tables in
/// columns.
///
/// ```
/// use monitor_host::aggregate::compare::{compare, NamedRun};
/// use monitor_host::{demo, score_run, Inputs, Settings};
/// let dir = tempfile::tempdir()?;
/// let run = demo::write(dir.path())?;
/// let inputs = Inputs { telemetry: Some(run.telemetry), ..Inputs::new([run.results]) };
/// let report = score_run(&inputs, &Settings::default())?;
/// let runs = vec![NamedRun { name: "a".into(), model: None, report: report.clone() },
///                 NamedRun { name: "b".into(), model: None, report }];
/// let html = monitor_host::report::html::compare_page(&compare(&runs, false), &runs);
/// assert!(html.contains("<section id=\"run-a\">") && html.contains("<section id=\"run-b\">"));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn compare_page(c: &Comparison, runs: &[crate::aggregate::compare::NamedRun]) -> String {
    let mut body =
        String::from("<h1>SDS comparison</h1>\n<p id=\"status\" hidden>script not run</p>\n");
    for g in table::compare_tables(c) {
        grid(&mut body, &g);
    }
    body.push_str("<h2>Runs side by side</h2>\n<div class=\"runs\">\n");
    for r in runs {
        body.push_str(&format!(
            "<section id=\"run-{}\"><h3>{}</h3>\n",
            escape(&r.name),
            escape(&r.name)
        ));
        grid(&mut body, &table::bench2drive_table(&r.report));
        grid(&mut body, &table::table1(&r.report));
        if let Some(g) = crate::report::protocol_table::protocol_table(&r.report) {
            grid(&mut body, &g);
        }
        body.push_str("</section>\n");
    }
    body.push_str("</div>\n");
    page::document("SDS comparison", &body)
}

/// A table of the text renderings as an HTML table (the same cells as text, Markdown, LaTeX).
fn grid(out: &mut String, g: &Grid) {
    out.push_str(&format!(
        "<table class=\"grid\"><caption>{}</caption>\n<thead><tr>",
        escape(&g.title)
    ));
    for h in &g.header {
        out.push_str(&format!("<th>{}</th>", escape(h)));
    }
    out.push_str("</tr></thead>\n<tbody>\n");
    let rows = g
        .rows
        .iter()
        .map(|r| (r, ""))
        .chain(g.total.iter().map(|r| (r, " class=\"total\"")));
    for (r, class) in rows {
        out.push_str(&format!("<tr{class}>"));
        for c in r {
            out.push_str(&format!("<td>{}</td>", escape(c)));
        }
        out.push_str("</tr>\n");
    }
    out.push_str("</tbody></table>\n");
    for n in &g.notes {
        out.push_str(&format!("<p class=\"note\">{}</p>\n", escape(n)));
    }
}
