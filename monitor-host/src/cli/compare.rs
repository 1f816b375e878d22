//! `sds compare` (spec v1.3 section 11): the command line over
//! [`crate::compare_runs::compare_runs`]. Runs are `NAME=RESULTS[:TELEMETRY]`; models are runs or
//! `--seeds` groups; the output is the `sds-compare/1` report or its tables; `--fail-if-worse`
//! exits 5 after writing it.

use std::path::{Path, PathBuf};

use anyhow::Result;

use super::args::{CompareArgs, Format};
use super::output::write_output;
use super::{style, EXIT_ROUTE_PROBLEMS, EXIT_USAGE, EXIT_WORSE};
use crate::aggregate::compare::CompareOptions;
use crate::compare_runs::{compare_runs, telemetry_beside, Compared, RunInputs, Seeds};
use crate::report::grid::Style;
use crate::report::{compare_table, html};
use crate::{Inputs, NoProgress};

/// A run argument: `NAME=RESULTS[:TELEMETRY]` or `RESULTS[:TELEMETRY]` (named by its folder or
/// file stem). A RESULTS path that exists as written is never split at a colon.
///
/// ```
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

/// The runs, seeds and options of the arguments.
///
/// # Errors
/// [`CompareUsage`] for a malformed `--seeds` or `--telemetry-of`, or one naming no run.
pub fn plan(
    args: &CompareArgs,
) -> Result<(Vec<RunInputs>, Vec<Seeds>, CompareOptions), CompareUsage> {
    let usage = |m: String| CompareUsage(m);
    let mut runs = Vec::new();
    for arg in &args.runs {
        let (name, results, telemetry) = parse_run(arg);
        runs.push(RunInputs {
            name,
            inputs: Inputs {
                telemetry: Some(telemetry.unwrap_or_else(|| telemetry_beside(&results))),
                results: vec![results],
                route_xml: args.run.routes.clone(),
                maps: args.run.maps.clone(),
            },
        });
    }
    for t in &args.telemetry_of {
        let Some((name, dir)) = t.split_once('=') else {
            return Err(usage(format!("--telemetry-of {t}: expected NAME=DIR")));
        };
        let Some(run) = runs.iter_mut().find(|r| r.name == name) else {
            return Err(usage(format!("--telemetry-of {t}: {name} is not a run")));
        };
        run.inputs.telemetry = Some(PathBuf::from(dir));
    }
    let mut seeds = Vec::new();
    for s in &args.seeds {
        let Some((model, list)) = s.split_once('=') else {
            return Err(usage(format!("--seeds {s}: expected MODEL=RUN,RUN,...")));
        };
        seeds.push(Seeds {
            model: model.to_string(),
            runs: list.split(',').map(|r| r.trim().to_string()).collect(),
        });
    }
    let options = CompareOptions {
        baseline: args.baseline.clone(),
        common_routes: args.common_routes,
        bootstrap_samples: args.bootstrap_samples,
        bootstrap_seed: args.bootstrap_seed,
        fail_if_worse: args
            .fail_if_worse
            .iter()
            .map(|m| m.trim().to_string())
            .collect(),
    };
    Ok((runs, seeds, options))
}

/// Scores and compares the runs of the arguments, printing each run's warnings; the second value
/// is true when some run has problem routes.
///
/// # Errors
/// A usage error, a run's error, or a comparison error.
pub fn compare_report(args: &CompareArgs) -> Result<(Compared, bool)> {
    let settings = args.run.settings(None)?;
    let (runs, seeds, options) = plan(args)?;
    let compared = compare_runs(&runs, &seeds, &settings, &options, &NoProgress)?;
    let mut problems = false;
    for m in &compared.models {
        for r in &m.runs {
            for w in &r.report.warnings {
                say!("sds: warning: {}: {w}", r.name);
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
        _ => crate::report::table::render(&compare_table::compare_tables(c), style).into_bytes(),
    };
    // Never write over any run's input.
    let inputs_read: Vec<PathBuf> = compared
        .models
        .iter()
        .flat_map(|m| &m.runs)
        .flat_map(|r| r.report.files_read.iter().cloned())
        .collect();
    write_output(args.output.as_deref(), &bytes, &inputs_read)?;
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
