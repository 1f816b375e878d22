//! `sds compare` (spec v1.4 section 11): the command line over the library's
//! [`CompareRequest`]. Runs are `NAME=RESULTS[:TELEMETRY]`; models are runs or
//! `--seeds` groups; the output is the `sds-compare/1` report or its tables; `--fail-if-worse`
//! exits 5 after writing it.

use std::path::{Path, PathBuf};

use anyhow::Result;

use super::args::{CompareArgs, Format};
use super::exit::{
    ROUTE_PROBLEMS as EXIT_ROUTE_PROBLEMS, USAGE as EXIT_USAGE, WORSE as EXIT_WORSE,
};
use super::output::write_output;
use super::style;
use monitor_host::app::compare_runs::{CompareRequest, Compared, RunSpec, Seeds};
use monitor_host::report::grid::Style;
use monitor_host::report::long_tables::{compare_tables, sweep_table, SWEEP_TABLE, TABLE_NAMES};
use monitor_host::report::{compare_table, html};
use monitor_host::stats::sweep::SweepAxis;
use monitor_host::stats::CompareOptions;
use monitor_host::{NoProgress, Warning};

/// A run argument: `NAME=RESULTS[:TELEMETRY]` or `RESULTS[:TELEMETRY]` (named by its folder or
/// file stem). A RESULTS path that exists as written is never split at a colon.
///
/// ```ignore
/// use monitor_host::cli::compare::parse_run;
/// use std::path::PathBuf;
/// assert_eq!(parse_run("new=out/r.json:out/tel"),
///            ("new".to_string(), PathBuf::from("out/r.json"), Some(PathBuf::from("out/tel"))));
/// assert_eq!(parse_run("runs/base.json").0, "base");
/// ```
pub fn parse_run(arg: &str) -> (String, PathBuf, Option<PathBuf>) {
    // An argument that exists as written is a path, even with `=` in it (a folder `lr=0.1`).
    let exists = std::fs::symlink_metadata(arg).is_ok();
    let (name, rest) = match arg.split_once('=').filter(|_| !exists) {
        Some((n, r)) if !n.is_empty() && !n.contains(['/', '\\']) => (Some(n), r),
        _ => (None, arg),
    };
    let (results, telemetry) = if Path::new(rest).exists() {
        (PathBuf::from(rest), None)
    } else {
        match rest.rsplit_once(':') {
            Some((r, t)) if !r.is_empty() && !t.is_empty() => {
                (PathBuf::from(r), Some(PathBuf::from(t)))
            }
            _ => (PathBuf::from(rest), None),
        }
    };
    let name = name.map_or_else(
        || {
            if results.is_dir() {
                results.file_name()
            } else {
                results.file_stem()
            }
            .map_or_else(|| rest.to_string(), |n| n.to_string_lossy().into_owned())
        },
        str::to_string,
    );
    (name, results, telemetry)
}

/// A usage error of `sds compare` (exit 2), with its message.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct CompareUsage(pub String);

/// The request of the arguments.
///
/// # Errors
/// [`CompareUsage`] for a malformed `--seeds` or `--telemetry-of`, or one naming no run;
/// [`monitor_host::settings::SettingsError`] for a `--set` without `=`.
pub fn request(args: &CompareArgs) -> Result<CompareRequest> {
    let usage = |m: String| CompareUsage(m);
    let settings = args.run.request(None, args.route_subset)?;
    let mut runs: Vec<RunSpec> = args
        .runs
        .iter()
        .map(|arg| {
            let (name, results, telemetry) = parse_run(arg);
            RunSpec {
                name,
                results,
                telemetry,
            }
        })
        .collect();
    for t in &args.telemetry_of {
        let Some((name, dir)) = t.split_once('=') else {
            return Err(usage(format!("--telemetry-of {t}: expected NAME=DIR")).into());
        };
        let Some(run) = runs.iter_mut().find(|r| r.name == name) else {
            return Err(usage(format!("--telemetry-of {t}: {name} is not a run")).into());
        };
        run.telemetry = Some(PathBuf::from(dir));
    }
    let mut seeds = Vec::new();
    for s in &args.seeds {
        let Some((model, list)) = s.split_once('=') else {
            return Err(usage(format!("--seeds {s}: expected MODEL=RUN,RUN,...")).into());
        };
        seeds.push(Seeds {
            model: model.to_string(),
            runs: list.split(',').map(|r| r.trim().to_string()).collect(),
        });
    }
    let sweep = args
        .sweep
        .iter()
        .map(|a| SweepAxis::parse(a).map_err(|e| usage(e.to_string())))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(CompareRequest {
        sweep,
        runs,
        seeds,
        routes: args.run.routes.clone(),
        maps: args.run.maps.clone(),
        settings,
        options: CompareOptions {
            baseline: args.baseline.clone(),
            common_routes: args.common_routes,
            bootstrap_samples: args.bootstrap_samples,
            bootstrap_seed: args.bootstrap_seed,
            fail_if_worse: args.fail_if_worse.clone(),
            rank: args.rank,
            repro_halfwidth: args.repro_halfwidth,
        },
    })
}

/// The runs' missing-map warnings ([`Warning::NoMap`], [`Warning::NoMaps`]) said once for the
/// whole comparison: every run is scored against the same `--maps` folder, so the towns are
/// listed once, and each run's count of routes in them (instead of one long line per run).
///
/// ```ignore
/// use monitor_host::cli::compare::maps_warning;
/// use monitor_host::Warning;
/// let w = |towns: &[(&str, usize)]| Warning::NoMaps {
///     towns: towns.iter().map(|(t, n)| (t.to_string(), *n)).collect(),
///     reason: "no map for Town03 in maps (looked for maps/Town03.xodr)".into(),
///     lane_fallback: false,
/// };
/// let a = w(&[("Town03", 11), ("Town12", 104)]);
/// let b = w(&[("Town03", 11), ("Town12", 100)]);
/// let line = maps_warning(&[("uniad", &a), ("vad", &b)], Some(std::path::Path::new("maps"))).unwrap();
/// assert_eq!(line, "no map in maps for 2 towns (Town03, Town12): their routes (uniad 115, vad 111) \
///     fall back to the route XML's straight segments; add the towns' .xodr to --maps to use their lanes");
/// ```
pub fn maps_warning(runs: &[(&str, &Warning)], maps: Option<&Path>) -> Option<String> {
    let mut towns = std::collections::BTreeSet::new();
    let mut per_run: Vec<(&str, usize)> = Vec::new();
    let mut lane = false;
    for (run, w) in runs {
        let (listed, lane_fallback) = match w {
            Warning::NoMap {
                town,
                routes,
                lane_fallback,
                ..
            } => (vec![(town.as_str(), *routes)], *lane_fallback),
            Warning::NoMaps {
                towns,
                lane_fallback,
                ..
            } => (
                towns.iter().map(|(t, n)| (t.as_str(), *n)).collect(),
                *lane_fallback,
            ),
            _ => continue,
        };
        lane |= lane_fallback;
        towns.extend(listed.iter().map(|(t, _)| *t));
        let routes: usize = listed.iter().map(|(_, n)| n).sum();
        match per_run.iter_mut().find(|(r, _)| r == run) {
            Some((_, n)) => *n += routes,
            None => per_run.push((run, routes)),
        }
    }
    if towns.is_empty() {
        return None;
    }
    let names: Vec<&str> = towns.into_iter().collect();
    let folder = maps.map_or_else(String::new, |m| format!(" in {}", m.display()));
    let counts: Vec<String> = per_run.iter().map(|(r, n)| format!("{r} {n}")).collect();
    Some(format!(
        "no map{folder} for {} town{} ({}): their routes ({}) fall back to the route XML's \
         straight segments{}; add the towns' .xodr to --maps to use their lanes",
        names.len(),
        if names.len() == 1 { "" } else { "s" },
        names.join(", "),
        counts.join(", "),
        if lane {
            " (lateral_reference=lane falls back to route)"
        } else {
            ""
        }
    ))
}

/// Scores and compares the runs of the arguments, printing each run's warnings (the missing
/// maps once for all runs: [`maps_warning`]); the second value is true when some run has
/// problem routes.
///
/// # Errors
/// A usage error, a run's error, or a comparison error.
pub fn compare_report(args: &CompareArgs) -> Result<(Compared, bool)> {
    let compared = request(args)?.compare(&NoProgress).map_err(super::failed)?;
    let mut problems = false;
    let mut no_maps: Vec<(&str, &Warning)> = Vec::new();
    for m in &compared.models {
        for r in &m.runs {
            for w in &r.report.warnings {
                if matches!(w, Warning::NoMap { .. } | Warning::NoMaps { .. }) {
                    no_maps.push((&r.name, w));
                } else {
                    say!("sds: warning: {}: {}", r.name, super::spelling::warning(w));
                }
            }
            if r.report.has_problems() {
                problems = true;
                say!(
                    "sds: {}: {} route(s) with problems (score it alone with sds score for details)",
                    r.name,
                    r.report.problem_routes().count()
                );
            }
        }
    }
    if let Some(w) = maps_warning(&no_maps, args.run.maps.as_deref()) {
        say!("sds: warning: {w}");
    }
    for w in &compared.comparison.warnings {
        say!("sds: warning: {w}");
    }
    Ok((compared, problems))
}

/// `sds compare`.
pub(super) fn compare(args: &CompareArgs) -> Result<i32> {
    let Some(style) = style(args.format)
        .or(matches!(args.format, Format::Json | Format::Html).then_some(Style::Text))
    else {
        say!("sds: error: sds compare writes json, table, markdown, latex or html, not csv");
        return Ok(EXIT_USAGE);
    };
    if let (Some(out), Some(dir)) = (&args.output, &args.tables) {
        let tables: Vec<_> = TABLE_NAMES[..2]
            .iter()
            .chain((!args.sweep.is_empty()).then_some(&SWEEP_TABLE))
            .map(|n| dir.join(n))
            .collect();
        super::output::refuse_clash(out, &tables, "a table")?;
    }
    let (compared, problems) = match compare_report(args) {
        Ok(x) => x,
        Err(e) if e.downcast_ref::<CompareUsage>().is_some() => {
            say!("sds: error: {e}");
            return Ok(EXIT_USAGE);
        }
        Err(e) => return Err(e),
    };
    let c = &compared.comparison;
    let bytes = match args.format {
        Format::Json => {
            let mut v = serde_json::to_vec_pretty(c)?;
            v.push(b'\n');
            v
        }
        Format::Html => html::compare_page(c, &compared.models).into_bytes(),
        _ => monitor_host::report::table::render(&compare_table::compare_tables(c), style)
            .into_bytes(),
    };
    // Never write over any run's input.
    let inputs_read: Vec<PathBuf> = compared
        .models
        .iter()
        .flat_map(|m| &m.runs)
        .flat_map(|r| r.report.files_read.iter().cloned())
        .collect();
    let tables = match &args.tables {
        Some(_) => {
            let runs: Vec<(&str, &str, &monitor_host::Report)> = compared
                .models
                .iter()
                .flat_map(|m| {
                    m.runs
                        .iter()
                        .map(move |r| (r.name.as_str(), m.name.as_str(), &r.report))
                })
                .collect();
            let mut t = compare_tables(&runs).map_err(anyhow::Error::msg)?;
            t.sweep = c.sweep.as_ref().map(sweep_table);
            Some(t.files().map_err(anyhow::Error::msg)?)
        }
        None => None,
    };
    // The tables, then the report, all or nothing (as `sds score`).
    let written = (|| -> Result<()> {
        if let (Some(dir), Some(files)) = (&args.tables, tables) {
            super::output::place_tables(dir, files, &inputs_read)?;
        }
        write_output(args.output.as_deref(), &bytes, &inputs_read)
    })();
    match written {
        Ok(()) => super::output::commit(),
        Err(e) => {
            super::output::roll_back();
            return Err(e);
        }
    }
    let failures = c.gate_failures();
    for f in &failures {
        say!("sds: gate: {f} (--fail-if-worse {})", f.metric);
    }
    Ok(if !failures.is_empty() {
        EXIT_WORSE
    } else if problems {
        EXIT_ROUTE_PROBLEMS
    } else {
        0
    })
}
