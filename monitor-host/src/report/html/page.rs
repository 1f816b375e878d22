//! The page's frame: document, heading, the run's warnings, escaping, and a table ([`Grid`]) as HTML.

use crate::report::grid::Grid;
use crate::report::Report;

const STYLE: &str = include_str!("report.css");
const SCRIPT: &str = include_str!("report.js");

/// Escapes text for HTML content and attribute values; control, bidirectional and invisible
/// format characters are shown as escapes ([`crate::report::escape::printable`]).
///
/// ```
/// assert_eq!(monitor_host::report::html::escape("a<b & \"c\""), "a&lt;b &amp; &quot;c&quot;");
/// assert_eq!(monitor_host::report::html::escape("r\u{202e}1"), "r\\u{202e}1");
/// ```
pub fn escape(s: &str) -> String {
    let mut o = String::with_capacity(s.len());
    for c in crate::report::escape::printable(s).chars() {
        match c {
            '&' => o.push_str("&amp;"),
            '<' => o.push_str("&lt;"),
            '>' => o.push_str("&gt;"),
            '"' => o.push_str("&quot;"),
            '\'' => o.push_str("&#39;"),
            c => o.push(c),
        }
    }
    o
}

/// A complete document: the style sheet, the body, then the script.
pub(super) fn document(title: &str, body: &str) -> String {
    format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
         <title>{}</title>\n<style>\n{STYLE}</style>\n</head>\n<body>\n{body}<script>\n{SCRIPT}</script>\n</body>\n</html>\n",
        escape(title)
    )
}

/// The page's heading: the run, its profile, and the headline numbers.
pub(super) fn heading(out: &mut String, report: &Report, name: &str) {
    let s = &report.summary;
    out.push_str(&format!(
        "<h1>SafeDriving Score: {}</h1>\n<p>{} routes · profile {} · SDS <b id=\"sds\">{}</b> · \
         DS {} · mean DS<sub>safe</sub> {} · mean comfort {}</p>\n\
         <p id=\"status\" hidden>script not run</p>\n",
        escape(name),
        report.routes.len(),
        report.profile,
        num(s.scores.sds, 2),
        num(s.scores.driving_score, 2),
        num(s.scores.mean_ds_safe, 2),
        num(s.scores.mean_comfort, 3),
    ));
}

/// The run's warnings, as the JSON report's `warnings` lists them (each route's warnings are
/// already there, named by their route: listed once).
pub(super) fn warnings(out: &mut String, report: &Report) {
    out.push_str(&format!(
        "<h2 id=\"run-warnings\">Warnings ({})</h2>\n<ul id=\"warnings\">\n",
        report.warnings.len()
    ));
    for w in &report.warnings {
        out.push_str(&format!(
            "<li class=\"warn\">{}</li>\n",
            escape(&w.to_string())
        ));
    }
    out.push_str("</ul>\n");
}

/// A number with `digits` decimals, `-` when absent.
pub(super) fn num(v: Option<f64>, digits: usize) -> String {
    v.map_or_else(|| "-".into(), |v| format!("{v:.digits$}"))
}

/// A table of the text renderings as an HTML table (the same cells as text, Markdown, LaTeX).
pub(super) fn grid(out: &mut String, g: &Grid) {
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
