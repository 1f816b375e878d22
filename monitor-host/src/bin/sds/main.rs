//! `sds`: the SafeDriving Score tool. See `sds --help` and the crate docs of `monitor_host`.
//!
//! The binary is thin: arguments, progress bar, output, exit codes. Everything else is the
//! library's [`monitor_host::score_run`].
//!
//! Exit codes: 0 success; 1 an input could not be read or the output not written (no report);
//! 2 usage error (bad option, a `--telemetry` folder that does not exist, duplicated route ids
//! under `--duplicates error`, N smaller than the routes counted, a label file that matches no
//! route); 3 the report was written but some route has a problem (missing or invalid telemetry
//! without `--allow-missing-telemetry`, an invalid record, or a streaming/batch disagreement) —
//! every such route is in the report with its state; 4 the inputs hold no record at all.

mod args;
mod output;
mod progress;

use anyhow::Result;
use clap::Parser;

use monitor_host::aggregate::groups::{GroupBy, Labels};
use monitor_host::input::labels::{check_coverage, read_labels};
use monitor_host::report::{csv, json, table};
use monitor_host::{
    demo, route_frames, score_run_with, Inputs, Report, Settings, TelemetryState, Warning,
};
use std::path::Path;

use args::{Cli, Command, Format, GroupArg, LayoutArg, ProfileArg, ScoreArgs};
use output::write_output;

/// Exit code: the report was written, but some route has a problem.
const EXIT_ROUTE_PROBLEMS: i32 = 3;
/// Exit code: a usage error (clap's own code too).
const EXIT_USAGE: i32 = 2;
/// Exit code: the inputs hold no record at all.
const EXIT_EMPTY_RUN: i32 = 4;

fn main() {
    let cli = Cli::parse();
    let code = match run(cli) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("sds: error: {e:#}");
            exit_code(&e)
        }
    };
    std::process::exit(code);
}

/// The exit code of an error: usage errors 2, an empty run 4, anything else 1.
fn exit_code(e: &anyhow::Error) -> i32 {
    use monitor_host::Error;
    if let Some(e) = e.downcast_ref::<Error>() {
        return match e {
            Error::Duplicates(_)
            | Error::TooFewRoutes { .. }
            | Error::TelemetryRoot { .. }
            | Error::Settings(_) => EXIT_USAGE,
            Error::EmptyRun { .. } => EXIT_EMPTY_RUN,
            _ => 1,
        };
    }
    if e.downcast_ref::<monitor_host::SettingsError>().is_some()
        || e.downcast_ref::<monitor_host::LabelsError>()
            .is_some_and(|l| matches!(l, monitor_host::LabelsError::NoMatch { .. }))
    {
        return EXIT_USAGE;
    }
    1
}

fn run(cli: Cli) -> Result<i32> {
    match cli.command {
        Command::Score(args) => score(&args),
        Command::Demo {
            dir,
            score: then_score,
            large,
            large_routes,
            large_frames,
            layout,
        } => {
            let run = if large {
                let layout = match layout {
                    LayoutArg::B2d => demo::LargeLayout::Bench2Drive,
                    LayoutArg::Wide => demo::LargeLayout::Wide,
                };
                demo::write_large_with(&dir, large_routes, large_frames, layout)?
            } else {
                demo::write(&dir)?
            };
            eprintln!(
                "sds: wrote {} routes to {} (results {}, telemetry {}, routes {})",
                run.route_ids.len(),
                dir.display(),
                run.results.display(),
                run.telemetry.display(),
                run.routes.display()
            );
            if !then_score {
                return Ok(0);
            }
            score(&ScoreArgs {
                results: vec![run.results],
                telemetry: Some(run.telemetry),
                routes: Some(run.routes),
                profile: ProfileArg::Physical,
                expected_routes: None,
                duplicates: None,
                allow_missing_telemetry: false,
                format: Format::Table,
                output: None,
                group_by: GroupArg::Scenario,
                families: None,
                weathers: None,
                set: vec![],
                jobs: None,
            })
        }
        Command::Frames {
            results,
            telemetry,
            routes,
            route_id,
            output,
        } => {
            let inputs = Inputs {
                results: vec![results],
                telemetry,
                route_xml: routes,
            };
            let run = route_frames(&inputs, &route_id, &Settings::default())?;
            for w in &run.warnings {
                eprintln!("sds: warning: {route_id}: {w}");
            }
            let mut out = Vec::new();
            let mut buf = [0u8; 512];
            for f in &run.frames {
                let n = monitor_core::json::encode(f, &mut buf)
                    .map_err(|e| anyhow::anyhow!("cannot encode a frame: {e}"))?;
                out.extend_from_slice(&buf[..n]);
                out.push(b'\n');
            }
            write_output(output.as_deref(), &out)?;
            Ok(0)
        }
    }
}

/// What a label file's keys are.
#[derive(Clone, Copy)]
enum LabelKey {
    Family,
    Weather,
}

/// Reads a label file and checks it against the report's routes: no key matching is an error,
/// keys of some routes without a label a warning (added to the report).
fn label_file(report: &mut Report, file: &Path, what: LabelKey) -> Result<Labels> {
    let labels = read_labels(file)?;
    let counted = report
        .routes
        .iter()
        .filter(|r| r.state != monitor_host::RouteState::Foreign);
    let (keys, name, option): (Vec<&str>, _, _) = match what {
        LabelKey::Family => (
            counted.filter_map(|r| r.scenario_type.as_deref()).collect(),
            "scenario type",
            "--families",
        ),
        LabelKey::Weather => (
            counted.filter_map(|r| r.weather_id.as_deref()).collect(),
            "weather id",
            "--weathers",
        ),
    };
    let unlabelled = check_coverage(&labels, keys, file, name, option)?;
    if !unlabelled.is_empty() {
        report.warnings.push(Warning::LabelsMissKeys {
            file: file.to_path_buf(),
            count: unlabelled.len(),
            keys: unlabelled.into_iter().take(8).collect(),
        });
    }
    Ok(labels)
}

/// The settings of `sds score`: its options, then `--set` overrides in order.
fn settings(args: &ScoreArgs) -> Result<Settings> {
    let mut s = Settings::default();
    s.core.profile = match args.profile {
        ProfileArg::Physical => monitor_core::Profile::Physical,
        ProfileArg::B2dLegacy => monitor_core::Profile::B2dLegacy,
    };
    s.expected_routes = args.expected_routes;
    if let Some(d) = args.duplicates {
        s.duplicates = d.policy();
    }
    s.allow_missing_telemetry = args.allow_missing_telemetry;
    s.threads = args.jobs;
    s.apply(&args.set)?;
    Ok(s)
}

fn score(args: &ScoreArgs) -> Result<i32> {
    let settings = settings(args)?;
    let inputs = Inputs {
        results: args.results.clone(),
        telemetry: args.telemetry.clone(),
        route_xml: args.routes.clone(),
    };
    let bar = progress::Bar::new();
    let report = score_run_with(&inputs, &settings, &bar);
    bar.finish();
    let mut report = report?;
    let families = args
        .families
        .as_deref()
        .map(|f| label_file(&mut report, f, LabelKey::Family))
        .transpose()?;
    let weathers = args
        .weathers
        .as_deref()
        .map(|f| label_file(&mut report, f, LabelKey::Weather))
        .transpose()?;

    // Every warning, the per-route ones included, is in the report; printed here once each.
    for w in &report.warnings {
        eprintln!("sds: warning: {w}");
    }
    let bytes = match args.format {
        Format::Json => json::json(&report)?,
        Format::Csv => csv::csv(&report),
        Format::Table => {
            let group = match args.group_by {
                GroupArg::Scenario => GroupBy::Scenario,
                GroupArg::Family => GroupBy::Family,
                GroupArg::Town => GroupBy::Town,
                GroupArg::Weather => GroupBy::Weather,
            };
            let labels = match group {
                GroupBy::Family => families.unwrap_or_default(),
                GroupBy::Weather => weathers.unwrap_or_default(),
                _ => Labels::new(),
            };
            table::table(&report, group, &labels).into_bytes()
        }
    };
    write_output(args.output.as_deref(), &bytes)?;

    // The exit status comes from the report's data, never from its rendering.
    if !report.has_problems() {
        return Ok(0);
    }
    if report.routes.is_empty() {
        eprintln!("sds: no route found in the results: nothing was scored");
    }
    // When no route has telemetry, the warning above said so once: no line per route.
    let no_telemetry = report.no_telemetry();
    for r in report.problem_routes() {
        if no_telemetry && matches!(r.telemetry, TelemetryState::Missing(_)) {
            continue;
        }
        eprintln!(
            "sds: {} ({}): {}",
            r.route_id.as_deref().unwrap_or("<no route_id>"),
            r.source.as_ref().map_or_else(
                || "-".into(),
                |s| format!("{}#{}", s.file.display(), s.index)
            ),
            r.state
        );
    }
    let s = &report.summary;
    if !s.batch_disagreements.is_empty() {
        eprintln!(
            "sds: streaming and batch disagree on {:?} (please report this bug)",
            s.batch_disagreements
        );
    }
    eprintln!(
        "sds: {} route(s) with telemetry problems, {} invalid record(s); see the report",
        s.telemetry_problems, s.invalid_records
    );
    Ok(EXIT_ROUTE_PROBLEMS)
}
