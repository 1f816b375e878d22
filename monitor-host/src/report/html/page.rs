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

/// The page of a live round of `sds watch` (docs/USAGE.md §8): `page` (the report's page, as `sds score`
/// writes it) with a tag that reloads it every `refresh` seconds and, first in its body, a banner
/// saying that it is live: the round and its time, routes done / N, DS over the routes done and
/// DS of N, the estimate of the time left. The final page of the watch has neither.
///
/// ```
/// use monitor_host::{report::html::live_page, RoundStatus};
/// let s = RoundStatus { round: 3, time: "2026-11-27T17:45:33Z".into(), done: 4, n: 9,
///                      ds_done: Some(80.0), ds_n: Some(35.56), seconds_left: Some(600.0),
///                      ..Default::default() };
/// let page = live_page("<html><head></head><body>\n<h1>x</h1></body></html>", &s, 10.0);
/// assert!(page.contains("<meta http-equiv=\"refresh\" content=\"10\">"));
/// assert!(page.contains("4 / 9 routes done"));
/// assert!(page.contains("DS 80.00 over the routes done, 35.56 of N"));
/// assert!(page.contains("about 10m left") && page.contains("2026-11-27T17:45:33Z"));
/// ```
pub fn live_page(page: &str, status: &crate::model::status::RoundStatus, refresh: f64) -> String {
    let tag = format!(
        "<meta http-equiv=\"refresh\" content=\"{}\">",
        refresh
            .ceil()
            .clamp(1.0, crate::model::status::MAX_INTERVAL)
    );
    let s = status;
    let banner = format!(
        "<p id=\"live\" role=\"status\" style=\"background:#fff3cd;border:1px solid #e0c060;\
         padding:.4em .6em\"><b>Live</b> · round {} at {} · {} / {} routes done · DS {} over the \
         routes done, {} of N · {} · this page reloads every {} s; the final report replaces it \
         when the watch stops</p>\n",
        s.round,
        escape(&s.time),
        s.done,
        s.n,
        num(s.ds_done, 2),
        num(s.ds_n, 2),
        s.seconds_left.map_or_else(
            || "time left unknown".to_string(),
            |t| format!("about {} left", crate::report::status::duration_text(t))
        ),
        refresh
            .ceil()
            .clamp(1.0, crate::model::status::MAX_INTERVAL)
    );
    let mut out = page.to_string();
    if let Some(i) = out.find("<body>") {
        let at = i + "<body>".len();
        let at = if out[at..].starts_with('\n') {
            at + 1
        } else {
            at
        };
        out.insert_str(at, &banner);
    } else {
        out.insert_str(0, &banner);
    }
    match out.find("<head>") {
        Some(i) => out.insert_str(i + "<head>".len(), &tag),
        None => out.insert_str(0, &tag),
    }
    out
}
