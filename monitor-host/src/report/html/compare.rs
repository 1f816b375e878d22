//! The comparison as one HTML page (`sds compare --format html`, docs/SCORE.md §10.3): the
//! tables at full width, the forest plot, the per-route values and deltas (sortable; each route
//! links to its row in each run), then each run's own tables and route rows.

use super::page::{self, escape, grid};
use crate::report::{compare_table, forest, table};
use crate::route::row::counted_routes;
use crate::stats::{Comparison, Model};

/// The anchor of a run's row of a route.
fn anchor(run: &str, route_id: &str) -> String {
    format!("run-{}-{}", escape(run), escape(route_id))
}

fn cell(v: Option<f64>, digits: usize, signed: bool) -> String {
    match v {
        Some(x) if signed => format!("<td data-v=\"{x}\">{x:+.digits$}</td>"),
        Some(x) => format!("<td data-v=\"{x}\">{x:.digits$}</td>"),
        None => "<td data-v=\"\">-</td>".to_string(),
    }
}

/// The page (see the module docs).
///
/// ```
/// use monitor_host::stats::{compare, CompareOptions, Model, NamedRun};
/// use monitor_host::{demo, score_run, Inputs, Settings};
/// let dir = tempfile::tempdir()?;
/// let run = demo::write(dir.path())?;
/// let inputs = Inputs { telemetry: Some(run.telemetry), ..Inputs::new([run.results]) };
/// let report = score_run(&inputs, &Settings::default())?;
/// let m = |n: &str| Model { name: n.into(), runs: vec![NamedRun { name: n.into(), report: report.clone() }] };
/// let models = [m("a"), m("b")];
/// let c = compare(&models, &CompareOptions::default())?;
/// let html = monitor_host::report::html::compare_page(&c, &models);
/// assert!(html.contains("<section id=\"run-a\">") && html.contains("id=\"per-route\""));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn compare_page(c: &Comparison, models: &[Model]) -> String {
    // The script's status line is for tests and errors (as on the score page): hidden, so a
    // reader never sees a stray "ok" under the heading.
    let mut body =
        String::from("<h1>SDS comparison</h1>\n<p id=\"status\" hidden>script not run</p>\n");
    body.push_str(&format!(
        "<p class=\"note\">baseline: {}; models: {}</p>\n",
        escape(&c.baseline),
        models
            .iter()
            .map(|m| {
                let runs: Vec<&str> = m.runs.iter().map(|r| r.name.as_str()).collect();
                if runs.len() > 1 {
                    format!("{} (seeds {})", escape(&m.name), escape(&runs.join(", ")))
                } else {
                    escape(&m.name)
                }
            })
            .collect::<Vec<_>>()
            .join(", ")
    ));
    for w in &c.warnings {
        body.push_str(&format!("<p class=\"warn\">{}</p>\n", escape(w)));
    }
    for g in compare_table::compare_tables(c) {
        body.push_str("<div class=\"wide\">\n");
        grid(&mut body, &g);
        body.push_str("</div>\n");
    }
    body.push_str(
        "<h2 id=\"forest\">Deltas against the baseline</h2>\n\
         <p class=\"note\">dot: delta (model − baseline); bar: 95 % bootstrap interval; green better, red worse, grey within noise; no data: no route compared (n = 0)</p>\n<div class=\"fig wide\">",
    );
    body.push_str(&forest::svg(c));
    body.push_str("</div>\n");
    body.push_str(&super::seeds::section(c));
    body.push_str(&super::sweep::section(c));
    per_route(&mut body, c, models);
    body.push_str("<h2>Runs</h2>\n");
    for m in models {
        for r in &m.runs {
            body.push_str(&format!(
                "<section id=\"run-{}\"><h3>{}{}</h3>\n<div class=\"wide\">\n",
                escape(&r.name),
                escape(&r.name),
                if m.runs.len() > 1 {
                    format!(" (seed of {})", escape(&m.name))
                } else {
                    String::new()
                }
            ));
            grid(&mut body, &table::bench2drive_table(&r.report));
            grid(&mut body, &table::table1(&r.report));
            if let Some(g) = crate::report::protocol_table::protocol_table(&r.report) {
                grid(&mut body, &g);
            }
            body.push_str("</div>\n<details><summary>routes</summary>\n<table class=\"grid\"><thead><tr><th>route</th><th>state</th><th>DS</th><th>success</th><th>DS_safe</th><th>comfort</th></tr></thead>\n<tbody>\n");
            for x in counted_routes(&r.report.routes) {
                let Some(id) = x.route_id.as_deref() else {
                    continue;
                };
                body.push_str(&format!(
                    "<tr id=\"{}\"><td>{}</td><td>{}</td>{}{}{}{}</tr>\n",
                    anchor(&r.name, id),
                    escape(id),
                    escape(x.state.name()),
                    cell(x.score_composed, 2, false),
                    cell(Some(if x.success { 1.0 } else { 0.0 }), 0, false),
                    cell(x.ds_safe, 2, false),
                    cell(x.comfort.score, 3, false),
                ));
            }
            body.push_str("</tbody></table></details>\n</section>\n");
        }
    }
    page::document("SDS comparison", &body)
}

/// The per-route table: each model's DS, then each other model's delta per metric.
fn per_route(out: &mut String, c: &Comparison, models: &[Model]) {
    let base = models
        .iter()
        .position(|m| m.name == c.baseline)
        .unwrap_or(0);
    out.push_str(&format!(
        "<h2>Per route</h2>\n<p class=\"note\">{} route key(s); click a heading to sort; a route's links open its row in each run</p>\n\
         <div class=\"wide\"><table id=\"per-route\" class=\"grid sortable\"><thead><tr><th data-col=\"route\">route</th><th>runs</th>",
        c.routes.len()
    ));
    for m in models {
        out.push_str(&format!(
            "<th data-col=\"ds:{0}\">DS {0}</th>",
            escape(&m.name)
        ));
    }
    for (_, m) in models.iter().enumerate().filter(|(i, _)| *i != base) {
        for metric in &c.metrics {
            out.push_str(&format!(
                "<th data-col=\"d{metric}:{0}\">Δ{metric} {0}</th>",
                escape(&m.name)
            ));
        }
    }
    out.push_str("</tr></thead>\n<tbody>\n");
    let runs: Vec<&str> = models
        .iter()
        .flat_map(|m| m.runs.iter().map(|r| r.name.as_str()))
        .collect();
    for (row, r) in c.routes.iter().enumerate() {
        let links: Vec<String> = runs
            .iter()
            .zip(&r.route_ids)
            .flat_map(|(run, ids)| {
                ids.iter()
                    .map(move |id| format!("<a href=\"#{}\">{}</a>", anchor(run, id), escape(run)))
            })
            .collect();
        out.push_str(&format!(
            "<tr data-i=\"{row}\" data-key=\"{0}\"><td>{0}</td><td>{1}</td>",
            escape(&r.key),
            links.join(" ")
        ));
        for v in &r.values {
            out.push_str(&cell(v[0], 2, false));
        }
        for (_, v) in r.values.iter().enumerate().filter(|(i, _)| *i != base) {
            for (k, metric) in c.metrics.iter().enumerate() {
                let d = v[k].zip(r.values[base][k]).map(|(a, b)| a - b);
                let digits = if *metric == "success" || *metric == "comfort" {
                    3
                } else {
                    2
                };
                out.push_str(&cell(d, digits, true));
            }
        }
        out.push_str("</tr>\n");
    }
    out.push_str("</tbody></table></div>\n");
}
