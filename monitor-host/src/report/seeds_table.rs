//! The tables of seeds and rankings (`sds compare`, docs/SCORE.md §10.3): the ranking a paper
//! can paste (`rank 2 [2, 3]`, with `--rank`), the seeds line per model (each seed's DS, their
//! std and the seeds a ±h interval needs), and the flaky routes (route, scenario, town, each
//! sample's outcome). Every cell goes through [`crate::report::grid`]'s escaping.

use crate::report::grid::Grid;
use crate::stats::rank::RankRow;
use crate::stats::Comparison;

fn num(x: Option<f64>, digits: usize) -> String {
    x.map_or_else(|| "-".into(), |v| format!("{v:.digits$}"))
}

/// `2 [2, 3]`: the rank and its 95 % interval (the rank alone when there is none; `-` without
/// a rank: no compared route).
pub fn rank_cell(r: &RankRow) -> String {
    match (r.rank, r.rank_ci95) {
        (Some(rank), Some([lo, hi])) => format!("{rank} [{lo}, {hi}]"),
        (Some(rank), None) => rank.to_string(),
        (None, _) => "-".into(),
    }
}

/// The ranking (when asked), the seeds line per model (when some model has several samples of
/// a route: seeds or repetitions), and the flaky routes (when there are any).
///
/// ```
/// use monitor_host::stats::{compare, CompareOptions, Model, NamedRun};
/// use monitor_host::report::{grid::Style, seeds_table::seed_tables, table::render};
/// use monitor_host::{demo, score_run, Inputs, Settings};
/// let dir = tempfile::tempdir()?;
/// let run = demo::write(dir.path())?;
/// let inputs = Inputs { telemetry: Some(run.telemetry), ..Inputs::new([run.results]) };
/// let report = score_run(&inputs, &Settings::default())?;
/// let m = |n: &str| Model { name: n.into(), runs: vec![NamedRun { name: n.into(), report: report.clone() }] };
/// let options = CompareOptions { rank: true, ..CompareOptions::default() };
/// let c = compare(&[m("base"), m("new")], &options)?;
/// let text = render(&seed_tables(&c), Style::Text);
/// // The same run twice: both first, in every resample.
/// assert!(text.lines().any(|l| l.starts_with("base") && l.contains("1 [1, 1]")));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn seed_tables(c: &Comparison) -> Vec<Grid> {
    let mut out = Vec::new();
    if let Some(ranking) = &c.ranking {
        let mut g = Grid::new(
            &format!(
                "Ranking by mean DS over {} route(s) (B = {} bootstrap resamples, seed {})",
                c.scope.routes, c.config.bootstrap_samples, c.config.bootstrap_seed
            ),
            ["model", "mean DS", "SDS", "rank [95% interval]", "p_best"],
        );
        for r in ranking {
            let sds = c
                .models
                .iter()
                .find(|m| m.name == r.model)
                .and_then(|m| m.sds.mean);
            g.row([
                r.model.clone(),
                num(r.mean_ds, 2),
                num(sds, 2),
                rank_cell(r),
                num(r.p_best, 3),
            ]);
        }
        g.note("rank = 1 + the models with a strictly greater mean DS; the interval and p_best (share of resamples ranked first) resample the routes");
        out.push(g);
    }
    let samples = c
        .models
        .iter()
        .any(|m| m.runs.len() > 1 || m.seeds.routes.iter().any(|r| r.ds_std.is_some()));
    if samples {
        let h = c.config.repro_halfwidth;
        let mut g = Grid::new(
            "Seeds: each seed's DS, their spread, and the seeds a 95% interval of the mean DS needs",
            [
                "model".to_string(),
                "seed DS".into(),
                "seed std".into(),
                format!("seeds for ±{h}"),
                "flaky routes".into(),
            ],
        );
        for m in &c.models {
            let ds: Vec<String> = m.seeds.seed_ds.iter().map(|d| num(*d, 2)).collect();
            g.row([
                m.name.clone(),
                ds.join(", "),
                num(m.seeds.seed_std, 2),
                m.seeds
                    .seeds_needed
                    .map_or_else(|| "-".into(), |n| n.to_string()),
                m.seeds.flaky_routes.len().to_string(),
            ]);
        }
        g.note("seed std is the sample std of the seeds' DS (- for one seed); seeds needed = ceil((1.96 × std / h)²), h = repro.halfwidth");
        out.push(g);
    }
    let flaky: Vec<_> = c
        .models
        .iter()
        .flat_map(|m| m.seeds.flaky.iter().map(move |f| (m, f)))
        .collect();
    if !flaky.is_empty() {
        let mut g = Grid::new(
            "Flaky routes: success in some samples and not in others",
            [
                "model",
                "route",
                "scenario",
                "town",
                "outcomes (run: DS pass/fail)",
            ],
        );
        for (m, f) in flaky {
            let outcomes: Vec<String> = f
                .outcomes
                .iter()
                .map(|o| {
                    let verdict = if o.success { "pass" } else { "fail" };
                    format!("{}: {:.1} {verdict}", o.run, o.ds)
                })
                .collect();
            g.row([
                m.name.clone(),
                f.route.clone(),
                f.scenario.clone().unwrap_or_else(|| "-".into()),
                f.town.clone().unwrap_or_else(|| "-".into()),
                outcomes.join("; "),
            ]);
        }
        g.note("a route is flaky when 0 < success share < 1 over the model's seeds and repetitions (each repetition a sample)");
        out.push(g);
    }
    out
}
