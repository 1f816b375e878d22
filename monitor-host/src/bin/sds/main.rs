//! `sds`: the SafeDriving Score tool. See `sds --help` and the crate docs of `monitor_host`.
//!
//! The binary is thin: arguments, progress bar, output, exit codes. Everything else is the
//! library's [`monitor_host::score_run`].
//!
//! Exit codes: 0 success; 1 an input could not be read or the output not written (no report);
//! 2 usage error; 3 the report was written but some route has a problem (missing or invalid
//! telemetry without `--allow-missing-telemetry`, an invalid record, or a streaming/batch
//! disagreement) — every such route is in the report with its state.

mod args;
mod output;
mod progress;

use anyhow::Result;
use clap::Parser;

use std::path::{Path, PathBuf};

use monitor_host::aggregate::compare::{compare, NamedRun};
use monitor_host::aggregate::groups::GroupBy;
use monitor_host::input::labels::read_labels;
use monitor_host::report::grid::Style;
use monitor_host::report::table::{self, TableOptions};
use monitor_host::report::{csv, html, json, Report};
use monitor_host::{demo, route_frames, score_run_with, Inputs, Settings};

use args::{Cli, Command, CompareArgs, Format, GroupArg, ProfileArg, ScoreArgs};
use output::write_output;

/// Exit code: the report was written, but some route has a problem.
const EXIT_ROUTE_PROBLEMS: i32 = 3;
/// Exit code: the command line asks for something impossible.
const EXIT_USAGE: i32 = 2;

fn main() {
    let cli = Cli::parse();
    let code = match run(cli) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("sds: error: {e:#}");
            1
        }
    };
    std::process::exit(code);
}

fn run(cli: Cli) -> Result<i32> {
    match cli.command {
        Command::Score(args) => score(&args),
        Command::Compare(args) => compare_runs(&args),
        Command::Demo {
            dir,
            score: then_score,
            large,
            large_routes,
            large_frames,
            large_collisions,
        } => {
            let run = if large {
                demo::write_large_with(&dir, large_routes, large_frames, large_collisions)?
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
            let html = dir.join("report.html");
            let code = score(&ScoreArgs {
                format: Format::Html,
                output: Some(html.clone()),
                traces: Some(dir.join("traces")),
                ..demo_args(&run)
            })?;
            eprintln!("sds: the demo's HTML report: {}", html.display());
            if code != 0 {
                return Ok(code);
            }
            score(&demo_args(&run))
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
                maps: None,
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

/// `sds score` of the demo run: the table on standard output.
fn demo_args(run: &demo::DemoRun) -> ScoreArgs {
    ScoreArgs {
        results: vec![run.results.clone()],
        telemetry: Some(run.telemetry.clone()),
        routes: Some(run.routes.clone()),
        maps: None,
        profile: ProfileArg::Physical,
        expected_routes: None,
        allow_missing_telemetry: false,
        format: Format::Table,
        output: None,
        group_by: None,
        families: None,
        weathers: None,
        infractions: vec![],
        set: vec![],
        jobs: None,
        traces: None,
    }
}

/// The settings of a run: the options, then `--set` overrides in order.
fn settings(
    profile: ProfileArg,
    expected_routes: Option<usize>,
    allow_missing_telemetry: bool,
    jobs: Option<usize>,
    set: &[String],
) -> Result<Settings> {
    let mut s = Settings::default();
    s.core.profile = match profile {
        ProfileArg::Physical => monitor_core::Profile::Physical,
        ProfileArg::B2dLegacy => monitor_core::Profile::B2dLegacy,
    };
    s.expected_routes = expected_routes;
    s.allow_missing_telemetry = allow_missing_telemetry;
    s.threads = jobs;
    s.apply(set)?;
    Ok(s)
}

/// Adds the breakdown the options ask for; the tables default to scenario types. `Ok(false)`
/// for a usage error (already printed).
fn add_groups(report: &mut Report, args: &ScoreArgs) -> Result<bool> {
    let tables = matches!(
        args.format,
        Format::Table | Format::Markdown | Format::Latex
    );
    let by = match (args.group_by, tables) {
        (Some(g), _) => g,
        (None, true) => GroupArg::Scenario,
        (None, false) => return Ok(true),
    };
    let (by, labels) = match by {
        GroupArg::Scenario => (GroupBy::Scenario, None),
        GroupArg::Town => (GroupBy::Town, None),
        GroupArg::Family => (GroupBy::Family, args.families.as_deref()),
        GroupArg::Weather => (GroupBy::Weather, args.weathers.as_deref()),
    };
    let labels = labels.map(read_labels).transpose()?;
    if let Err(e) = report.group(by, labels.as_ref()) {
        eprintln!("sds: error: {e}");
        return Ok(false);
    }
    Ok(true)
}

fn style(format: Format) -> Option<Style> {
    match format {
        Format::Table => Some(Style::Text),
        Format::Markdown => Some(Style::Markdown),
        Format::Latex => Some(Style::Latex),
        Format::Json | Format::Csv | Format::Html => None,
    }
}

fn score(args: &ScoreArgs) -> Result<i32> {
    let settings = settings(
        args.profile,
        args.expected_routes,
        args.allow_missing_telemetry,
        args.jobs,
        &args.set,
    )?;
    if args.group_by == Some(GroupArg::Family) && args.families.is_none() {
        eprintln!("sds: error: --group-by family needs its label map (--families FILE)");
        return Ok(EXIT_USAGE);
    }
    let inputs = Inputs {
        results: args.results.clone(),
        telemetry: args.telemetry.clone(),
        route_xml: args.routes.clone(),
        maps: args.maps.clone(),
    };
    let bar = progress::Bar::new();
    let report = score_run_with(&inputs, &settings, &bar);
    bar.finish();
    let mut report = report?;
    if !add_groups(&mut report, args)? {
        return Ok(EXIT_USAGE);
    }

    for w in &report.warnings {
        eprintln!("sds: warning: {w}");
    }
    for r in &report.routes {
        for w in &r.warnings {
            let id = r.route_id.as_deref().unwrap_or("<no route_id>");
            eprintln!("sds: warning: {id}: {w}");
        }
    }
    let bytes = match (args.format, style(args.format)) {
        (Format::Json, _) => json::json(&report)?,
        (Format::Csv, _) => csv::groups_csv(&report).unwrap_or_else(|| csv::csv(&report)),
        (Format::Html, _) => {
            html::page(&report, &table_options(args), &run_name(args)).into_bytes()
        }
        (_, Some(style)) => {
            table::render(&table::report_tables(&report, &table_options(args)), style).into_bytes()
        }
        (_, None) => unreachable!("every table format has a style"),
    };
    write_output(args.output.as_deref(), &bytes)?;
    if let Some(dir) = &args.traces {
        let n = output::write_traces(dir, &report)?;
        eprintln!("sds: wrote {n} collision trace(s) to {}", dir.display());
    }
    report_problems(&report)
}

fn table_options(args: &ScoreArgs) -> TableOptions {
    TableOptions {
        extra_infractions: args.infractions.clone(),
    }
}

/// The run's name in the HTML page: the results argument(s).
fn run_name(args: &ScoreArgs) -> String {
    args.results
        .iter()
        .map(|p| p.display().to_string())
        .collect::<Vec<_>>()
        .join(", ")
}

/// Tells what makes the exit status fail (from the report's data, never its rendering) and
/// returns the exit status.
fn report_problems(report: &Report) -> Result<i32> {
    if !report.has_problems() {
        return Ok(0);
    }
    if report.routes.is_empty() {
        eprintln!("sds: no route found in the results: nothing was scored");
    }
    for r in report.problem_routes() {
        eprintln!(
            "sds: {} ({}): {}",
            r.route_id.as_deref().unwrap_or("<no route_id>"),
            r.source,
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

/// A run of `sds compare`: `NAME=PATH` or `PATH` (named by its folder or file stem).
fn parse_run(arg: &str) -> (String, PathBuf) {
    if let Some((name, path)) = arg.split_once('=') {
        if !name.is_empty() && !name.contains(['/', '\\']) {
            return (name.to_string(), PathBuf::from(path));
        }
    }
    let path = PathBuf::from(arg);
    let name = if path.is_dir() {
        path.file_name()
    } else {
        path.file_stem()
    }
    .map_or_else(|| arg.to_string(), |n| n.to_string_lossy().into_owned());
    (name, path)
}

/// The telemetry root of a run: its folder (a results file's own folder).
fn telemetry_of(path: &Path) -> PathBuf {
    if path.is_dir() {
        path.to_path_buf()
    } else {
        path.parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."))
            .to_path_buf()
    }
}

fn compare_runs(args: &CompareArgs) -> Result<i32> {
    let Some(style) = style(args.format)
        .or(matches!(args.format, Format::Json | Format::Html).then_some(Style::Text))
    else {
        eprintln!("sds: error: sds compare writes json, table, markdown, latex or html, not csv");
        return Ok(EXIT_USAGE);
    };
    let settings = settings(
        args.profile,
        args.expected_routes,
        args.allow_missing_telemetry,
        args.jobs,
        &args.set,
    )?;
    let mut seeds: Vec<(String, String)> = Vec::new();
    for s in &args.seeds {
        let Some((model, runs)) = s.split_once('=') else {
            eprintln!("sds: error: --seeds {s}: expected MODEL=RUN,RUN,...");
            return Ok(EXIT_USAGE);
        };
        seeds.extend(
            runs.split(',')
                .map(|r| (r.trim().to_string(), model.to_string())),
        );
    }
    let mut runs = Vec::new();
    let mut problems = false;
    for arg in &args.runs {
        let (name, path) = parse_run(arg);
        if runs.iter().any(|r: &NamedRun| r.name == name) {
            eprintln!("sds: error: two runs are named {name}: name them with NAME=PATH");
            return Ok(EXIT_USAGE);
        }
        let inputs = Inputs {
            results: vec![path.clone()],
            telemetry: Some(telemetry_of(&path)),
            route_xml: args.routes.clone(),
            maps: args.maps.clone(),
        };
        let report = score_run_with(&inputs, &settings, &monitor_host::NoProgress)?;
        for w in &report.warnings {
            eprintln!("sds: warning: {name}: {w}");
        }
        if report.has_problems() {
            problems = true;
            eprintln!(
                "sds: {name}: {} route(s) with problems (score it alone with sds score for details)",
                report.problem_routes().count()
            );
        }
        let model = seeds
            .iter()
            .find(|(r, _)| *r == name)
            .map(|(_, m)| m.clone());
        runs.push(NamedRun {
            name,
            model,
            report,
        });
    }
    for (run, _) in &seeds {
        if !runs.iter().any(|r| &r.name == run) {
            eprintln!("sds: error: --seeds names {run}, which is not a run");
            return Ok(EXIT_USAGE);
        }
    }
    let route_set = args.routes.is_some() || args.expected_routes.is_some();
    let comparison = compare(&runs, route_set);
    let bytes = if args.format == Format::Json {
        let mut v = serde_json::to_vec_pretty(&comparison)?;
        v.push(b'\n');
        v
    } else if args.format == Format::Html {
        html::compare_page(&comparison, &runs).into_bytes()
    } else {
        table::render(&table::compare_tables(&comparison), style).into_bytes()
    };
    write_output(args.output.as_deref(), &bytes)?;
    Ok(if problems { EXIT_ROUTE_PROBLEMS } else { 0 })
}
