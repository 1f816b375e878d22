//! `sds compare` (docs/SCORE.md §10.3): the command line over the library's
//! [`CompareRequest`]. Runs are `NAME=RESULTS[:TELEMETRY]`; models are runs or
//! `--seeds` groups; the output is the `sds-compare/1` report or its tables; `--fail-if-worse`
//! exits 5 after writing it.

use std::path::{Path, PathBuf};

use anyhow::Result;

use super::args::CompareArgs;
use super::exit::{
    ROUTE_PROBLEMS as EXIT_ROUTE_PROBLEMS, USAGE as EXIT_USAGE, WORSE as EXIT_WORSE,
};
use super::output::write_output;
use monitor_host::report::long_tables::{compare_tables, sweep_table, SWEEP_TABLE, TABLE_NAMES};
use monitor_host::report::render::{self, CompareFormatError, COMPARE_FORMATS};
use monitor_host::stats::sweep::SweepAxis;
use monitor_host::stats::CompareOptions;
use monitor_host::NoProgress;
use monitor_host::{CompareRequest, CompareWarning, Compared, RunSpec, Seeds};

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

/// Scores and compares the runs of the arguments, printing each run's warnings (the missing
/// maps once for all runs: [`Compared::warnings`]); the second value is true when some run has
/// problem routes.
///
/// # Errors
/// A usage error, a run's error, or a comparison error.
pub fn compare_report(args: &CompareArgs) -> Result<(Compared, bool)> {
    let compared = request(args)?.compare(&NoProgress).map_err(super::failed)?;
    let warnings = compared.warnings(args.run.maps.as_deref());
    let mut problems = false;
    for r in compared.models.iter().flat_map(|m| &m.runs) {
        // Each run's warnings, then its problem routes.
        for w in &warnings {
            if let CompareWarning::Run { run, warning } = w {
                if *run == r.name {
                    let class = if warning.is_note() { "note" } else { "warning" };
                    say!("sds: {class}: {run}: {}", super::spelling::warning(warning));
                }
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
    for w in &warnings {
        if let CompareWarning::Comparison(text) = w {
            say!("sds: warning: {text}");
        }
    }
    Ok((compared, problems))
}

/// `sds compare`.
pub(super) fn compare(args: &CompareArgs) -> Result<i32> {
    if !COMPARE_FORMATS.contains(&args.format) {
        say!(
            "sds: error: {}",
            CompareFormatError::Unsupported(args.format)
        );
        return Ok(EXIT_USAGE);
    }
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
    let bytes = render::render_compare(c, &compared.models, args.format)?;
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
