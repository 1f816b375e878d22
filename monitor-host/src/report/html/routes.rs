//! The route table (sortable, filterable: the script) and each route's drill-down.

use crate::report::figure;
use crate::report::Report;
use crate::route::row::RouteReport;
use crate::route::trace::Verdict;

use super::page::{escape, num};
use super::timeline::{self, FIGURES_PER_ROUTE};

/// A results file as a shared page names it: its folder and file name, never the path above
/// (`10857/checkpoint_endpoint.json`; the JSON report keeps the path as found).
fn shared_name(path: &std::path::Path) -> String {
    let parts: Vec<String> = path
        .components()
        .filter_map(|c| match c {
            std::path::Component::Normal(n) => Some(n.to_string_lossy().into_owned()),
            _ => None,
        })
        .collect();
    parts[parts.len().saturating_sub(2)..].join("/")
}

/// The id of route `i`'s drill-down (route ids may repeat under `duplicates = all`).
fn target(i: usize) -> String {
    format!("route-{i}")
}

/// Counts of a route's aligned collisions by verdict: (decelerated, no deceleration, exempt).
fn verdicts(r: &RouteReport) -> (usize, usize, usize) {
    let of = |v: Verdict| {
        r.collision_events
            .iter()
            .filter(|e| Verdict::of(e) == Some(v))
            .count()
    };
    (
        of(Verdict::Decelerated),
        of(Verdict::NoDeceleration),
        of(Verdict::Exempt),
    )
}

/// A numeric cell: the full value in `data-v` (what sorting and the tests read), rounded text.
fn cell(v: Option<f64>, digits: usize) -> String {
    format!(
        "<td data-v=\"{}\">{}</td>",
        v.map_or(String::new(), |v| v.to_string()),
        num(v, digits)
    )
}

fn count(n: usize) -> String {
    format!("<td data-v=\"{n}\">{n}</td>")
}

/// A penalty factor as a person writes it: at most 4 decimals, no trailing zeros (`0.6`,
/// `0.42`, `1`), so that `0.6 * 0.7` reads 0.42, not 0.41999999999999998.
fn factor(v: f64) -> String {
    let s = format!("{v:.4}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".into()
    } else {
        s.into()
    }
}

/// Why a route's DS is what it is, from its record: the evaluator's status, route completion
/// and penalty (`Failed - TickRuntime, RC 50.53 × penalty 0.6 = 30.32`); a route without a
/// record says so.
fn outcome(r: &RouteReport) -> String {
    let status = r.status.as_deref().unwrap_or("no record");
    match (r.score_route, r.score_penalty, r.score_composed) {
        (Some(rc), Some(p), ds) => format!(
            "{status}, RC {rc:.2} × penalty {} = {}",
            factor(p),
            num(ds, 2)
        ),
        _ => format!("{status}, DS {}", num(r.score_composed, 2)),
    }
}

/// The columns: (key the test hook sorts by, header).
const COLUMNS: [(&str, &str); 20] = [
    ("route", "route"),
    ("state", "state"),
    ("town", "town"),
    ("scenario", "scenario"),
    ("status", "status"),
    ("rc", "RC"),
    ("penalty", "penalty"),
    ("ds", "DS"),
    ("ds_safe", "DS_safe"),
    ("comfort", "comfort"),
    ("comfort_moving", "comfort (moving)"),
    ("stationary", "stationary %"),
    ("collisions", "collisions"),
    ("decelerated", "decelerated"),
    ("nodecel", "no decel."),
    ("exempt", "exempt"),
    ("unaligned", "unaligned"),
    ("anomalous", "lat. anom."),
    ("critical", "lat. crit."),
    ("warnings", "warnings"),
];

/// The route table with its filter controls.
pub(super) fn route_table(out: &mut String, report: &Report) {
    let figures: usize = report
        .routes
        .iter()
        .map(|r| r.traces.len().min(FIGURES_PER_ROUTE))
        .sum();
    let mut states: Vec<String> = report.routes.iter().map(state_name).collect();
    states.sort();
    states.dedup();
    out.push_str(
        "<h2 id=\"route-list\">Routes</h2>\n<div class=\"controls\">\
        <input id=\"filter\" type=\"search\" placeholder=\"filter: route, town, scenario…\">\
        <select id=\"state\"><option value=\"\">every state</option>",
    );
    for s in &states {
        out.push_str(&format!("<option value=\"{0}\">{0}</option>", escape(s)));
    }
    out.push_str("</select><span id=\"shown\"></span></div>\n");
    out.push_str(&format!(
        "<div class=\"wide\"><table id=\"routes\" data-routes=\"{}\" data-figures=\"{figures}\">\n<thead><tr>",
        report.routes.len()
    ));
    for (key, head) in COLUMNS {
        out.push_str(&format!("<th data-col=\"{key}\">{head}</th>"));
    }
    out.push_str("</tr></thead>\n<tbody>\n");
    for (i, r) in report.routes.iter().enumerate() {
        let id = r.route_id.as_deref().unwrap_or("<no route_id>");
        let (dec, nodecel, exempt) = verdicts(r);
        let c = &r.collisions;
        let state = state_name(r);
        out.push_str(&format!(
            "<tr data-i=\"{i}\" data-route=\"{}\" data-state=\"{}\" data-target=\"{}\">\
             <td><a href=\"#{}\">{}</a></td><td class=\"st-{}\" title=\"{}\">{}</td><td>{}</td><td>{}</td>",
            escape(id),
            escape(&state),
            target(i),
            target(i),
            escape(id),
            escape(&state),
            escape(&r.state.to_string()),
            escape(&state),
            escape(r.town.as_deref().unwrap_or("")),
            escape(r.scenario_type.as_deref().unwrap_or("")),
        ));
        // The status in full in the cell, the arithmetic behind the DS in its tooltip.
        out.push_str(&format!(
            "<td class=\"status\" title=\"{}\">{}</td>",
            escape(&outcome(r)),
            escape(r.status.as_deref().unwrap_or("-"))
        ));
        out.push_str(&cell(r.score_route, 2));
        out.push_str(&cell(r.score_penalty, 3));
        out.push_str(&cell(r.score_composed, 2));
        out.push_str(&cell(r.ds_safe, 2));
        out.push_str(&cell(r.comfort.score, 3));
        out.push_str(&cell(r.comfort.moving_score, 3));
        out.push_str(&cell(r.stationary_share.map(|s| 100.0 * s), 1));
        out.push_str(&count((c.pedestrian + c.vehicle + c.layout) as usize));
        out.push_str(&count(dec));
        out.push_str(&if nodecel > 0 {
            format!("<td class=\"nodecel\" data-v=\"{nodecel}\">{nodecel}</td>")
        } else {
            count(0)
        });
        out.push_str(&count(exempt));
        out.push_str(&count(c.unaligned as usize));
        out.push_str(&count(r.lateral.anomalous as usize));
        out.push_str(&count(r.lateral.critical as usize));
        out.push_str(&count(r.warnings.len()));
        out.push_str("</tr>\n");
    }
    out.push_str("</tbody></table></div>\n");
}

/// `scored`, `missing`, ... without an invalid route's reason.
fn state_name(r: &RouteReport) -> String {
    let s = r.state.to_string();
    s.split(':').next().unwrap_or_default().to_string()
}

/// Each route's drill-down: figures, timelines, warnings.
pub(super) fn drill_downs(out: &mut String, report: &Report) {
    out.push_str("<h2 id=\"details\">Route details</h2>\n");
    let chunk_len = report.config.core.chunk_len;
    for (i, r) in report.routes.iter().enumerate() {
        let id = r.route_id.as_deref().unwrap_or("<no route_id>");
        out.push_str(&format!(
            "<details class=\"route\" id=\"{}\" data-route=\"{}\"><summary><b>{}</b> · {} · DS {} · DS<sub>safe</sub> {} · comfort {} · {} collision event(s)</summary>\n",
            target(i),
            escape(id),
            escape(id),
            escape(&r.state.to_string()),
            num(r.score_composed, 2),
            num(r.ds_safe, 2),
            num(r.comfort.score, 3),
            r.collision_events.len(),
        ));
        out.push_str(&format!(
            "<p class=\"outcome\">{}</p>\n",
            escape(&outcome(r))
        ));
        if let Some(src) = &r.source {
            out.push_str(&format!(
                "<p>source {}#{}</p>\n",
                escape(&shared_name(&src.file)),
                src.index
            ));
        }
        if let Some(reason) = &r.reason {
            out.push_str(&format!("<p class=\"warn\">{}</p>\n", escape(reason)));
        }
        timeline::events(out, r, i);
        for t in r.traces.iter().take(FIGURES_PER_ROUTE) {
            out.push_str(&format!(
                "<div class=\"fig\" id=\"{}-collision-{}\">",
                target(i),
                t.event
            ));
            out.push_str(&figure::svg(t));
            out.push_str("</div>\n");
        }
        let more = r
            .collision_events
            .iter()
            .filter(|e| e.frame.is_some())
            .count();
        let more = more.saturating_sub(r.traces.len().min(FIGURES_PER_ROUTE));
        if more > 0 && !r.traces.is_empty() {
            out.push_str(&format!(
                "<p class=\"note more-figures\">and {more} more aligned collision(s) without a \
                 figure here (at most {FIGURES_PER_ROUTE} per route; every collision is in the \
                 JSON report's events)</p>\n"
            ));
        }
        let unaligned = r
            .collision_events
            .iter()
            .filter(|e| e.frame.is_none())
            .count();
        if unaligned > 0 {
            out.push_str(&format!(
                "<p>{unaligned} collision(s) not aligned to a frame: no figure.</p>\n"
            ));
        }
        match &r.chunks {
            Some(chunks) => {
                timeline::comfort(out, chunks, chunk_len, &r.stationary);
                timeline::lateral(out, chunks, r.lateral.chunks, chunk_len);
            }
            None => out.push_str("<p>No telemetry replayed: no timeline.</p>\n"),
        }
        if !r.warnings.is_empty() {
            out.push_str("<ul>");
            for w in &r.warnings {
                out.push_str(&format!(
                    "<li class=\"warn\">{}</li>",
                    escape(&w.to_string())
                ));
            }
            out.push_str("</ul>\n");
        }
        out.push_str("</details>\n");
    }
}
