//! The seeds and the ranking on the comparison page (docs/SCORE.md §10.3): the models in the
//! order given (the checkpoints of one training run read left to right) with each model's mean
//! DS and SDS and its rank with the rank's 95 % interval, and per flaky route a strip of its
//! outcomes across the model's seeds and repetitions (one square per sample: green success,
//! red failure, the run and DS in its tooltip).
//!
//! Hand-written SVG: the same comparison gives the same bytes, and every name from the user
//! goes through [`escape`].

use super::page::escape;
use crate::stats::Comparison;

/// Width of one model's column in the ranking figure, px.
const COL: f64 = 64.0;
/// The figure's left margin (axis labels), px.
const LEFT: f64 = 48.0;
/// A sample's square in the strip, px.
const CELL: f64 = 14.0;

fn num(x: Option<f64>) -> String {
    x.map_or_else(|| "-".into(), |v| format!("{v:.2}"))
}

/// The section: the ranking figure (with `--rank`) and the strips of the flaky routes (when a
/// model has any); empty when there is neither.
///
/// ```
/// use monitor_host::stats::{compare, CompareOptions, Model, NamedRun};
/// use monitor_host::{demo, score_run, Inputs, Settings};
/// let dir = tempfile::tempdir()?;
/// let run = demo::write(dir.path())?;
/// let inputs = Inputs { telemetry: Some(run.telemetry), ..Inputs::new([run.results]) };
/// let report = score_run(&inputs, &Settings::default())?;
/// let m = |n: &str| Model { name: n.into(), runs: vec![NamedRun { name: n.into(), report: report.clone() }] };
/// let models = [m("ep10"), m("ep20")];
/// let ranked = compare(&models, &CompareOptions { rank: true, ..CompareOptions::default() })?;
/// let html = monitor_host::report::html::seeds::section(&ranked);
/// assert!(html.contains("id=\"ranking\"") && html.contains(">ep20</text>"));
/// let plain = compare(&models, &CompareOptions::default())?;
/// assert_eq!(monitor_host::report::html::seeds::section(&plain), "");
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn section(c: &Comparison) -> String {
    let mut out = String::new();
    if let Some(svg) = ranking_svg(c) {
        out.push_str(&format!(
            "<h2 id=\"ranking\">Ranking</h2>\n<p class=\"note\">models in the order given; top: mean DS (dots) and SDS (squares); bottom: rank (dot) and its 95 % bootstrap interval (bar) over B = {} resamples of the routes, seed {}; rank = 1 + the models with a strictly greater mean DS</p>\n<div class=\"fig wide\">{svg}</div>\n",
            c.config.bootstrap_samples, c.config.bootstrap_seed
        ));
    }
    if let Some(html) = flaky_strips(c) {
        out.push_str(&html);
    }
    out
}

/// The ranking figure: per model in the order given, its mean DS and SDS (0 to 100, top
/// panel) and its rank with the interval (bottom panel, rank 1 at the top).
pub fn ranking_svg(c: &Comparison) -> Option<String> {
    let ranking = c.ranking.as_ref()?;
    let n = c.models.len();
    if n == 0 {
        return None;
    }
    let width = LEFT + COL * n as f64 + 16.0;
    // Top panel: y 20..180 for 100..0; bottom panel: y 220..(220 + 24 n) for ranks 1..n.
    let (top, bottom) = (20.0, 180.0);
    let rank_top = 220.0;
    let rank_step = 24.0;
    let rank_bottom = rank_top + rank_step * (n.saturating_sub(1)) as f64;
    let height = rank_bottom + 70.0;
    let x = |i: usize| LEFT + COL * (i as f64 + 0.5);
    let y_score = |v: f64| bottom - (v.clamp(0.0, 100.0) / 100.0) * (bottom - top);
    let y_rank = |r: f64| rank_top + (r - 1.0) * rank_step;
    let mut s = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width:.0}\" height=\"{height:.0}\" viewBox=\"0 0 {width:.0} {height:.0}\" font-family=\"sans-serif\" font-size=\"11\">\n"
    );
    // Axes and grid.
    for v in [0.0, 25.0, 50.0, 75.0, 100.0] {
        let y = y_score(v);
        s.push_str(&format!(
            "<line x1=\"{LEFT}\" y1=\"{y:.1}\" x2=\"{:.1}\" y2=\"{y:.1}\" stroke=\"#eee\"/><text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"end\">{v:.0}</text>\n",
            width - 16.0,
            LEFT - 6.0,
            y + 4.0
        ));
    }
    s.push_str(&format!(
        "<text x=\"4\" y=\"{:.1}\">score</text>\n<text x=\"4\" y=\"{:.1}\">rank</text>\n",
        top - 6.0,
        rank_top - 12.0
    ));
    for r in 1..=n {
        let y = y_rank(r as f64);
        s.push_str(&format!(
            "<line x1=\"{LEFT}\" y1=\"{y:.1}\" x2=\"{:.1}\" y2=\"{y:.1}\" stroke=\"#eee\"/><text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"end\">{r}</text>\n",
            width - 16.0,
            LEFT - 6.0,
            y + 4.0
        ));
    }
    // Each model's DS and SDS, joined in the order given (a training run's curve).
    let ds: Vec<Option<f64>> = c
        .models
        .iter()
        .map(|m| {
            ranking
                .iter()
                .find(|r| r.model == m.name)
                .and_then(|r| r.mean_ds)
        })
        .collect();
    let sds: Vec<Option<f64>> = c.models.iter().map(|m| m.sds.mean).collect();
    for (values, colour) in [(&ds, "#1f5fbf"), (&sds, "#d07a00")] {
        let points: Vec<String> = values
            .iter()
            .enumerate()
            .filter_map(|(i, v)| v.map(|v| format!("{:.1},{:.1}", x(i), y_score(v))))
            .collect();
        if points.len() > 1 {
            s.push_str(&format!(
                "<polyline points=\"{}\" fill=\"none\" stroke=\"{colour}\" stroke-width=\"1.5\"/>\n",
                points.join(" ")
            ));
        }
    }
    for (i, m) in c.models.iter().enumerate() {
        let name = escape(&m.name);
        if let Some(v) = ds[i] {
            s.push_str(&format!(
                "<circle cx=\"{:.1}\" cy=\"{:.1}\" r=\"4\" fill=\"#1f5fbf\"><title>{name}: mean DS {v:.2}</title></circle>\n",
                x(i),
                y_score(v)
            ));
        }
        if let Some(v) = sds[i] {
            s.push_str(&format!(
                "<rect x=\"{:.1}\" y=\"{:.1}\" width=\"7\" height=\"7\" fill=\"#d07a00\"><title>{name}: SDS {v:.2}</title></rect>\n",
                x(i) - 3.5,
                y_score(v) - 3.5
            ));
        }
        // No rank (no compared route): nothing to draw on the rank axis.
        if let Some((r, rank)) = ranking
            .iter()
            .find(|r| r.model == m.name)
            .and_then(|r| Some((r, r.rank?)))
        {
            if let Some([lo, hi]) = r.rank_ci95 {
                s.push_str(&format!(
                    "<line x1=\"{0:.1}\" y1=\"{1:.1}\" x2=\"{0:.1}\" y2=\"{2:.1}\" stroke=\"#555\" stroke-width=\"5\" stroke-linecap=\"round\" opacity=\"0.45\"/>\n",
                    x(i),
                    y_rank(lo as f64),
                    y_rank(hi as f64)
                ));
            }
            let ci = r
                .rank_ci95
                .map_or_else(String::new, |[lo, hi]| format!(" [{lo}, {hi}]"));
            s.push_str(&format!(
                "<circle cx=\"{:.1}\" cy=\"{:.1}\" r=\"4.5\" fill=\"#222\"><title>{name}: rank {}{ci}, p_best {}</title></circle>\n",
                x(i),
                y_rank(rank as f64),
                rank,
                r.p_best.map_or_else(|| "-".into(), |p| format!("{p:.3}"))
            ));
        }
        // The model's name, and its figures under it.
        s.push_str(&format!(
            "<text x=\"{0:.1}\" y=\"{1:.1}\" text-anchor=\"middle\">{name}</text>\n<text x=\"{0:.1}\" y=\"{2:.1}\" text-anchor=\"middle\" fill=\"#666\" font-size=\"9\">{3} / {4}</text>\n",
            x(i),
            rank_bottom + 30.0,
            rank_bottom + 44.0,
            num(ds[i]),
            num(sds[i])
        ));
    }
    s.push_str(&format!(
        "<text x=\"{LEFT}\" y=\"{:.1}\" fill=\"#666\" font-size=\"9\">under each model: mean DS / SDS</text>\n</svg>",
        height - 6.0
    ));
    Some(s)
}

/// Per model with flaky routes, one row per flaky route: the route, its scenario and town, and
/// one square per sample in the order of the model's runs.
pub fn flaky_strips(c: &Comparison) -> Option<String> {
    if c.models.iter().all(|m| m.seeds.flaky.is_empty()) {
        return None;
    }
    let mut out = String::from(
        "<h2 id=\"flaky\">Flaky routes</h2>\n<p class=\"note\">routes that succeeded in some samples and failed in others (0 &lt; success share &lt; 1); one square per seed or repetition, in the order of the model's runs: green success, red failure (hover for the run and its DS)</p>\n",
    );
    for m in c.models.iter().filter(|m| !m.seeds.flaky.is_empty()) {
        out.push_str(&format!(
            "<h3>{} ({} flaky route(s))</h3>\n<table class=\"grid flaky\"><thead><tr><th>route</th><th>scenario</th><th>town</th><th>outcomes</th></tr></thead>\n<tbody>\n",
            escape(&m.name),
            m.seeds.flaky.len()
        ));
        for f in &m.seeds.flaky {
            let k = f.outcomes.len() as f64;
            let mut svg = format!(
                "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{0:.0}\" height=\"{1:.0}\" viewBox=\"0 0 {0:.0} {1:.0}\">",
                CELL * k + 2.0,
                CELL + 2.0
            );
            for (j, o) in f.outcomes.iter().enumerate() {
                let (fill, verdict) = if o.success {
                    ("#2aa05a", "success")
                } else {
                    ("#c82828", "failure")
                };
                svg.push_str(&format!(
                    "<rect class=\"{verdict}\" x=\"{:.1}\" y=\"1\" width=\"{:.1}\" height=\"{:.1}\" fill=\"{fill}\"><title>{}: DS {:.1}, {verdict}</title></rect>",
                    1.0 + CELL * j as f64,
                    CELL - 2.0,
                    CELL - 2.0,
                    escape(&o.run),
                    o.ds
                ));
            }
            svg.push_str("</svg>");
            out.push_str(&format!(
                "<tr><td>{}</td><td>{}</td><td>{}</td><td class=\"strip\">{svg}</td></tr>\n",
                escape(&f.route),
                escape(f.scenario.as_deref().unwrap_or("-")),
                escape(f.town.as_deref().unwrap_or("-"))
            ));
        }
        out.push_str("</tbody></table>\n");
    }
    Some(out)
}
