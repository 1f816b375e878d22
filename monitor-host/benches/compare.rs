//! What `sds compare` adds to scoring (`harness = false`): [`compare`] (route keys, per-model
//! values, the same-route-set check, B bootstrap resamples per model and metric, flips) over 10
//! runs of 220 routes, each its own model (9 compared with the baseline), B = 10,000.
//!
//! Usage: `cargo bench -p monitor-host --bench compare [-- RUNS ROUTES B REPEATS SEEDS RANK]`
//! (SEEDS runs per model, default 1; RANK 1 adds `--rank`, docs/SCORE.md §10.3). The runs are
//! one scored `sds demo --large` run (40 frames a route, so comfort is defined) copied with
//! per-route scores changed deterministically, so that no two models are equal. Prints
//! `runs=R routes=N B=B min_s=.. median_s=.. cpu_s=..` (cpu: this process, every thread).

use std::time::Instant;

use monitor_host::stats::{compare, CompareOptions, Model, NamedRun};
use monitor_host::{demo, score_run, Inputs, Settings};

fn main() {
    let args: Vec<usize> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    let arg = |i: usize, d: usize| args.get(i).copied().unwrap_or(d);
    let (runs, routes, b, repeats) = (arg(0, 10), arg(1, 220), arg(2, 10_000), arg(3, 5));
    let dir = tempfile::tempdir().expect("temp dir");
    let run = demo::write_large(dir.path(), routes, 40).expect("demo run");
    let inputs = Inputs {
        telemetry: Some(run.telemetry),
        route_xml: Some(run.routes),
        ..Inputs::new([run.results])
    };
    let report = score_run(&inputs, &Settings::default()).expect("scored");
    // SEEDS > 1 groups the runs into models of SEEDS runs each (seeds of one model, docs/SCORE.md §10.3).
    let seeds = arg(4, 1).max(1);
    let rank = arg(5, 0) == 1;
    let perturbed = |m: usize| {
        let mut r = report.clone();
        for (i, route) in r.routes.iter_mut().enumerate() {
            // A fixed, different pattern per run: DS, success and DS_safe move together.
            let k = ((i * 31 + m * 17) % 101) as f64 / 100.0;
            route.score_composed = Some(100.0 * k);
            route.ds_safe = Some(90.0 * k);
            route.success = k > 0.5;
        }
        NamedRun {
            name: format!("r{m}"),
            report: r,
        }
    };
    let models: Vec<Model> = (0..runs / seeds)
        .map(|m| Model {
            name: format!("m{m}"),
            runs: (0..seeds).map(|s| perturbed(m * seeds + s)).collect(),
        })
        .collect();
    let options = CompareOptions {
        bootstrap_samples: b,
        rank,
        ..CompareOptions::default()
    };
    let cpu0 = cpu_s();
    let mut times: Vec<f64> = (0..repeats)
        .map(|_| {
            let t = Instant::now();
            let c = compare(&models, &options).expect("compared");
            assert_eq!(c.paired.len(), (models.len() - 1) * 4);
            assert_eq!(c.ranking.is_some(), rank);
            t.elapsed().as_secs_f64()
        })
        .collect();
    let cpu = (cpu_s() - cpu0) / repeats as f64;
    times.sort_by(f64::total_cmp);
    println!(
        "runs={runs} seeds={seeds} rank={rank} routes={routes} B={b} min_s={:.3} median_s={:.3} cpu_s={cpu:.3}",
        times[0],
        times[times.len() / 2]
    );
}

/// This process's CPU time (user + system, every thread), from /proc; 0 where it is missing.
fn cpu_s() -> f64 {
    let Ok(stat) = std::fs::read_to_string("/proc/self/stat") else {
        return 0.0;
    };
    // Fields after the command name: utime and stime are the 12th and 13th.
    let rest = stat.rsplit(')').next().unwrap_or("");
    let f: Vec<f64> = rest
        .split_whitespace()
        .skip(11)
        .take(2)
        .filter_map(|x| x.parse().ok())
        .collect();
    f.iter().sum::<f64>() / 100.0
}
