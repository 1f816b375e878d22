//! The comparison's tables (`sds compare`, docs/SCORE.md §10.3): Bench2Drive's main table and
//! Safe2Drive Table 1 with one row per model (mean ± std over seeds where there are seeds), the
//! paired table (per model and metric: delta, 95 % interval, `p_better`, verdict), and the flips.
//! Rendered as text, Markdown or LaTeX by [`crate::report::grid`].

use crate::report::grid::Grid;
use crate::report::table::{BENCH2DRIVE_COLUMNS, TABLE1_COLUMNS};
use crate::stats::models::Stat;
use crate::stats::Comparison;

/// `mean ± std` (std only when there are seeds), scaled, or `-`.
fn stat(s: &Stat, digits: usize, scale: f64) -> String {
    match (s.mean, s.std) {
        (Some(m), Some(sd)) => format!("{:.digits$} ± {:.digits$}", m * scale, sd * scale),
        (Some(m), None) => format!("{:.digits$}", m * scale),
        _ => "-".into(),
    }
}

fn signed(x: Option<f64>, digits: usize) -> String {
    x.map_or_else(|| "-".into(), |v| format!("{v:+.digits$}"))
}

/// Digits for a metric: DS-like scores 2, success and comfort (0..1) 3.
fn digits(metric: &str) -> usize {
    if metric == "success" || metric == "comfort" {
        3
    } else {
        2
    }
}

/// The per-model tables, the paired table and the flips.
///
/// ```
/// use monitor_host::stats::{compare, CompareOptions, Model, NamedRun};
/// use monitor_host::report::{compare_table::compare_tables, grid::Style, table::render};
/// use monitor_host::{demo, score_run, Inputs, Settings};
/// let dir = tempfile::tempdir()?;
/// let run = demo::write(dir.path())?;
/// let inputs = Inputs { telemetry: Some(run.telemetry), ..Inputs::new([run.results]) };
/// let report = score_run(&inputs, &Settings::default())?;
/// let m = |n: &str| Model { name: n.into(), runs: vec![NamedRun { name: n.into(), report: report.clone() }] };
/// let c = compare(&[m("base"), m("new")], &CompareOptions::default())?;
/// let text = render(&compare_tables(&c), Style::Markdown);
/// assert!(text.contains("| new | ds |") && text.contains("within noise"));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn compare_tables(c: &Comparison) -> Vec<Grid> {
    let seeds = c.models.iter().any(|m| m.runs.len() > 1);
    let over = if seeds {
        " (mean ± sample std over seeds)"
    } else {
        ""
    };
    // The ability rule, named as `sds score`'s table names it (one rule, or each model's).
    let rules: Vec<&str> = c.models.iter().map(|m| m.ability_rule).collect();
    let rule = match rules.first() {
        Some(r) if rules.iter().all(|x| x == r) => format!(", ability rule {r}"),
        _ => String::new(),
    };
    let mut b2d = Grid::new(
        &format!("Bench2Drive: closed-loop metrics and multi-ability (%){over}{rule}"),
        ["model", "runs"].into_iter().chain(BENCH2DRIVE_COLUMNS),
    );
    let mut t1 = Grid::new(
        &format!("Safe2Drive Table 1: SafeDriving Score{over}"),
        ["model", "runs"]
            .into_iter()
            .chain(TABLE1_COLUMNS)
            .chain(["Coll.(%)"]),
    );
    for m in &c.models {
        let a = &m.ability;
        b2d.row([
            m.name.clone(),
            m.runs.len().to_string(),
            stat(&m.driving_score, 2, 1.0),
            stat(&m.success_rate, 2, 1.0),
            stat(&m.efficiency, 2, 1.0),
            stat(&m.smoothness, 2, 100.0),
            stat(&a.merging, 2, 100.0),
            stat(&a.overtaking, 2, 100.0),
            stat(&a.emergency_brake, 2, 100.0),
            stat(&a.give_way, 2, 100.0),
            stat(&a.traffic_signs, 2, 100.0),
            stat(&a.mean, 2, 100.0),
        ]);
        t1.row([
            m.name.clone(),
            m.runs.len().to_string(),
            stat(&m.driving_score, 2, 1.0),
            stat(&m.success_rate, 2, 1.0),
            stat(&m.mean_ds_safe, 2, 1.0),
            stat(&m.mean_comfort, 3, 1.0),
            stat(&m.mean_comfort_moving, 3, 1.0),
            stat(&m.mean_stationary_share, 2, 100.0),
            stat(&m.sds, 2, 1.0),
            stat(&m.collision_rate, 2, 1.0),
        ]);
    }
    if rule.is_empty() && !c.models.is_empty() {
        let each: Vec<String> = c
            .models
            .iter()
            .map(|m| format!("{} {}", m.name, m.ability_rule))
            .collect();
        b2d.note(format!("ability rules differ: {}", each.join(", ")));
    }
    // Each run's undecided junction credits and the bracket its Traffic Sign rate lies in, as
    // `sds score`'s table says them (issue 46 item 6: compare's tables left them out).
    for m in &c.models {
        for (run, b) in &m.bench2drive {
            if let Some(note) = crate::report::table::undecided_note(b) {
                b2d.note(format!("{run}: {note}"));
            }
        }
    }
    if c.models.iter().all(|m| m.ability.mean.mean.is_none()) {
        b2d.note("no ability rate: abilities need the route XML (routes) and routes of Bench2Drive's scenario types");
    }
    for m in c.models.iter().filter(|m| m.runs.len() > 1) {
        t1.note(format!("{}: seeds {}", m.name, m.runs.join(", ")));
    }
    let scope = if c.scope.common_routes {
        format!(
            "compared on the {} route key(s) every run holds (common_routes)",
            c.scope.routes
        )
    } else {
        format!(
            "compared on {} route key(s), the same in every run",
            c.scope.routes
        )
    };
    t1.note(scope.clone());
    let mut paired = Grid::new(
        &format!(
            "Paired comparison against the baseline {} (per route, B = {} bootstrap resamples, seed {})",
            c.baseline, c.config.bootstrap_samples, c.config.bootstrap_seed
        ),
        ["model", "metric", "n", "delta", "95% interval", "p_better", "verdict"],
    );
    for p in &c.paired {
        let d = digits(&p.metric);
        paired.row([
            p.model.clone(),
            p.metric.clone(),
            p.result.n.to_string(),
            signed(p.result.delta, d),
            p.result
                .ci95
                .map_or_else(|| "-".into(), |[lo, hi]| format!("[{lo:+.d$}, {hi:+.d$}]")),
            p.result
                .p_better
                .map_or_else(|| "-".into(), |x| format!("{x:.3}")),
            p.result.verdict.map_or("-", |v| v.name()).to_string(),
        ]);
    }
    paired.note("delta = model − baseline, the mean over the routes compared; comfort leaves out routes where it is undefined");
    for n in &c.notes {
        paired.note(n.clone());
    }
    let mut flips = Grid::new(
        &format!("Flips against the baseline {}", c.baseline),
        [
            "model",
            "regressed",
            "fixed",
            "largest |ΔDS| (route: delta)",
        ],
    );
    for f in &c.flips {
        let few = |v: &[String]| -> String {
            let mut s = v.len().to_string();
            if !v.is_empty() {
                let head: Vec<&str> = v.iter().take(5).map(String::as_str).collect();
                s.push_str(&format!(
                    " ({}{})",
                    head.join(", "),
                    if v.len() > 5 { ", ..." } else { "" }
                ));
            }
            s
        };
        let largest: Vec<String> = f
            .largest
            .iter()
            .filter(|m| m.delta != 0.0)
            .take(3)
            .map(|m| format!("{}: {:+.2}", m.key, m.delta))
            .collect();
        flips.row([
            f.model.clone(),
            few(&f.regressed),
            few(&f.fixed),
            largest.join(", "),
        ]);
    }
    flips.note("regressed: success 1 -> 0; fixed: 0 -> 1 (success fraction over seeds); the JSON report lists all, and the top 10 moves");
    let mut out = vec![b2d, t1, paired, flips];
    // docs/SCORE.md §10.3: the ranking, the seeds line and the flaky routes.
    out.extend(crate::report::seeds_table::seed_tables(c));
    // docs/SCORE.md §10.4: the sweep, one row per point.
    out.extend(crate::report::sweep_table::sweep_tables(c));
    out
}
