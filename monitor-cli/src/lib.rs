//! The `sds` command line (crate `sds-cli`): arguments, progress bar, output, exit codes.
//! Everything else is the library's [`monitor_host::score_run`]. The `sds` binary and the Python
//! package's `sds` command both call [`main`] with their argument list, so they are one program.
//!
//! Exit codes ([`exit`]): 0 success; 1 no report (an input could not be read, the output not
//! written); 2 a usage error (an option, or inputs that do not fit the options); 3 the report
//! was written but some route has a problem (every such route is in the report with its state);
//! 4 the inputs hold no record at all; 5 (`sds compare --fail-if-worse`) a model is worse than
//! the baseline on a gated metric. An error's code is [`exit::code`] of its
//! [`monitor_host::ErrorKind`].

mod args;
mod output;
mod progress;

/// Prints one message on standard error, escaped: it may hold strings from the inputs (route
/// ids, paths, reasons), which must not reach the terminal raw
/// ([`monitor_host::report::escape::printable_lines`]).
/// A closed standard error loses the message, never panics (`eprintln!` would on EPIPE).
macro_rules! say {
    ($($t:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(
            std::io::stderr(),
            "{}",
            monitor_host::report::escape::printable_lines(&format!($($t)*))
        );
    }};
}

mod compare;
pub mod exit;
mod link;
mod merge;
mod spelling;
mod watch;

use std::ffi::OsString;

use anyhow::Result;
use clap::Parser;

use monitor_host::aggregate::groups::GroupBy;
use monitor_host::report::long_tables;
use monitor_host::report::render::{self, RenderOptions};
use monitor_host::report::table::TableOptions;
use monitor_host::{demo, Inputs, LabelFiles, Progress, SettingsError, TelemetryState};
use monitor_host::{Frames, FramesRequest};
use monitor_host::{ScoreError, ScoreRequest};

use args::{Cli, Command, Format, ScoreArgs};

pub use monitor_host::Scored;
use output::write_output;

/// Runs the `sds` command line with `args` (the first is the program name, as in
/// `std::env::args_os()`) and returns the exit code. Never exits the process: usage errors,
/// `--help` and `--version` print and return their code (2, 0, 0).
///
/// ```
/// assert_eq!(sds_cli::main(["sds", "--version"]), 0);
/// assert_eq!(sds_cli::main(["sds", "score"]), 2); // --results is required
/// ```
pub fn main<I, T>(args: I) -> i32
where
    I: IntoIterator<Item = T>,
    T: Into<OsString> + Clone,
{
    let cli = match Cli::try_parse_from(args) {
        Ok(cli) => cli,
        Err(e) => {
            let _ = e.print();
            return e.exit_code();
        }
    };
    match output::install_signal_cleanup().and_then(|()| run(cli)) {
        Ok(code) => code,
        Err(e) => {
            say!("sds: error: {}{}", error_message(&*e), spelling::suffix(&e));
            exit::of(&e)
        }
    }
}

/// The text `sds` prints for an error that stops it (`sds: error: <text>`): the error and each
/// of its causes, joined by `": "`, a cause that the text already ends with written once. The
/// bindings raise their exceptions with the same text.
///
/// ```ignore
/// use monitor_host::input::results_file::read_results;
/// let e = read_results(std::path::Path::new("/nonexistent")).unwrap_err();
/// assert_eq!(monitor_host::cli::error_message(&e),
///            "/nonexistent: cannot read: No such file or directory (os error 2)");
/// ```
pub fn error_message(e: &(dyn std::error::Error + 'static)) -> String {
    monitor_host::error::message(e)
}

fn run(cli: Cli) -> Result<i32> {
    match cli.command {
        Command::Score(args) => score(&args),
        Command::Compare(args) => compare::compare(&args),
        Command::Watch(args) => watch::watch(&args),
        Command::Merge(args) => merge::merge(&args),
        Command::Link(args) => link::link(&args),
        Command::Checker(args) => link::checker(&args),
        Command::Demo {
            dir,
            score: then_score,
            large,
            large_routes,
            large_frames,
            layout,
            large_collisions,
            force,
        } => {
            let mut existing = demo::existing_run(&dir);
            if then_score {
                // `--score` writes these too: never over an earlier report without --force.
                existing.extend(
                    ["report.html", "traces", "figures"]
                        .iter()
                        .map(|n| dir.join(n))
                        .filter(|p| std::fs::symlink_metadata(p).is_ok()),
                );
            }
            if !existing.is_empty() && !force {
                let names: Vec<String> = existing.iter().map(|p| p.display().to_string()).collect();
                anyhow::bail!(
                    "{} already holds a run ({}); pass --force to overwrite it",
                    dir.display(),
                    names.join(", ")
                );
            }
            let run = if large {
                demo::write_large_with(&dir, large_routes, large_frames, layout, large_collisions)?
            } else {
                demo::write(&dir)?
            };
            say!(
                "sds: wrote {} routes to {} (results {}, telemetry {}, routes {}, maps {})",
                run.route_ids.len(),
                dir.display(),
                run.results.display(),
                run.telemetry.display(),
                run.routes.display(),
                run.maps.display()
            );
            if !then_score {
                return Ok(0);
            }
            let html = dir.join("report.html");
            let code = score(&ScoreArgs {
                format: Format::Html,
                output: Some(html.clone()),
                traces: Some(dir.join("traces")),
                figures: Some(dir.join("figures")),
                ..demo_args(&run)?
            })?;
            say!("sds: the demo's HTML report: {}", html.display());
            if code != 0 {
                return Ok(code);
            }
            score(&demo_args(&run)?)
        }
        Command::Frames(args) => {
            let request = FramesRequest {
                inputs: Inputs {
                    results: args.results,
                    telemetry: args.telemetry,
                    route_xml: args.run.routes.clone(),
                    maps: args.run.maps.clone(),
                },
                settings: args.run.request(args.duplicates, None)?,
                route_id: args.route_id,
                log: args.mcap,
                topics: args.topics,
            };
            let Frames { route_id, frames } = request.frames().map_err(failed)?;
            for w in &frames.warnings {
                say!("sds: warning: {route_id}: {}", spelling::warning(w));
            }
            let lines =
                monitor_host::report::frames::frame_lines(&frames).map_err(anyhow::Error::msg)?;
            write_output(args.output.as_deref(), &lines, &frames.files_read)?;
            Ok(0)
        }
    }
}

/// The request of `sds score` (and of `sds watch`'s run): the files, the options (`--set`
/// last), the label files, the breakdown (`--group-by`, or by scenario for the table formats).
///
/// # Errors
/// A `--set` without `=`.
pub fn request(args: &ScoreArgs) -> Result<ScoreRequest, SettingsError> {
    Ok(ScoreRequest {
        inputs: inputs(args),
        settings: args.run.request(args.duplicates, args.route_subset)?,
        labels: label_files(args),
        group_by: args
            .group_by
            .or(args.format.style().map(|_| GroupBy::Scenario)),
        infractions: args.infractions.clone(),
        logs: args.mcap.clone(),
        topics: args.topics.clone(),
    })
}

/// The files `sds score` reads.
pub fn inputs(args: &ScoreArgs) -> Inputs {
    Inputs {
        results: args.results.clone(),
        telemetry: args.telemetry.clone(),
        route_xml: args.run.routes.clone(),
        maps: args.run.maps.clone(),
    }
}

/// A request's error as the command line reports it (its exit code from the error inside).
fn failed(e: ScoreError) -> anyhow::Error {
    match e {
        ScoreError::Request(e) => e.into(),
        ScoreError::Run(e) => e.into(),
        ScoreError::Tables(m) => anyhow::Error::msg(m),
    }
}

/// The label files `sds score` reads.
fn label_files(args: &ScoreArgs) -> LabelFiles {
    LabelFiles {
        families: args.families.clone(),
        weathers: args.weathers.clone(),
        routes: args.labels.clone(),
    }
}

/// Everything `sds score` does before rendering: its [`request`], scored (telling `progress`).
///
/// # Errors
/// A typed error inside (a [`monitor_host::Error`], [`monitor_host::RequestError`] or [`SettingsError`];
/// `downcast_ref` tells which).
pub fn score_report(args: &ScoreArgs, progress: &dyn Progress) -> Result<Scored> {
    request(args)?.score(progress).map_err(failed)
}

/// `sds score` of the demo run: the table on standard output. Parsed as the command line
/// would parse it, so an option added to `sds score` needs nothing here.
fn demo_args(run: &demo::DemoRun) -> Result<ScoreArgs> {
    let argv: [&std::ffi::OsStr; 12] = [
        "sds".as_ref(),
        "score".as_ref(),
        "--results".as_ref(),
        run.results.as_os_str(),
        "--telemetry".as_ref(),
        run.telemetry.as_os_str(),
        "--routes".as_ref(),
        run.routes.as_os_str(),
        "--maps".as_ref(),
        run.maps.as_os_str(),
        "--format".as_ref(),
        "table".as_ref(),
    ];
    match Cli::try_parse_from(argv)?.command {
        Command::Score(args) => Ok(args),
        other => anyhow::bail!("the demo's arguments parsed as {other:?}, not sds score"),
    }
}

/// The rendering options of `sds score` (and of `sds watch`'s rounds: `live`).
fn render_options<'a>(
    args: &ScoreArgs,
    live: Option<(f64, &'a monitor_host::RoundStatus)>,
) -> RenderOptions<'a> {
    RenderOptions {
        tables: TableOptions {
            extra_infractions: args.infractions.clone(),
        },
        name: render::run_name(&args.results),
        live,
    }
}

/// Writes the report in `args.format` to `-o` or standard output, as `sds score` and `sds
/// watch` write it (JSON streamed: a large run's text is never held beside its report).
fn write_report(
    args: &ScoreArgs,
    out: Option<&std::path::Path>,
    report: &monitor_host::Report,
    live: Option<(f64, &monitor_host::RoundStatus)>,
    inputs_read: &[std::path::PathBuf],
) -> Result<()> {
    let options = render_options(args, live);
    output::write_output_with(out, inputs_read, &|w| {
        render::write(report, args.format, &options, w)
    })
}

fn score(args: &ScoreArgs) -> Result<i32> {
    refuse_output_clashes(args)?;
    let bar = progress::Bar::new();
    let scored = score_report(args, &bar);
    bar.finish();
    let Scored { report, .. } = scored?;

    // Every warning and note, the per-route ones included, is in the report; printed here
    // once each.
    for w in &report.warnings {
        say!("sds: {}", spelling::line(w));
    }
    let inputs_read = request(args)?.inputs_read(&report);
    write_all(args, &report, &inputs_read, || {
        write_report(args, args.output.as_deref(), &report, None, &inputs_read)
    })?;

    // The exit status comes from the report's data, never from its rendering.
    if !report.has_problems() {
        return Ok(0);
    }
    if report.routes.is_empty() {
        say!("sds: no route found in the results: nothing was scored");
    }
    // When no route has telemetry, the warning above said so once: no line per route.
    let no_telemetry = report.no_telemetry();
    for r in report.problem_routes() {
        if no_telemetry && matches!(r.telemetry, TelemetryState::Missing(_)) {
            continue;
        }
        let state = r.state.to_string();
        let id = r.route_id.as_deref().unwrap_or("<no route_id>");
        match &r.source {
            // A vehicle log's reason names its file already: not twice.
            Some(s) if state.contains(&s.file.display().to_string()) => {
                say!("sds: {id}: {state}")
            }
            Some(s) => say!("sds: {id} ({}#{}): {state}", s.file.display(), s.index),
            None => say!("sds: {id} (-): {state}"),
        }
    }
    let s = &report.summary;
    if !s.batch_disagreements.is_empty() {
        say!(
            "sds: streaming and batch disagree on {:?} (please report this bug)",
            s.batch_disagreements
        );
    }
    // Only the counts that are not zero (a `0 invalid record(s)` reads as a problem).
    let counts: Vec<String> = [
        (s.telemetry_problems, "route(s) with telemetry problems"),
        (s.invalid_records, "invalid record(s)"),
    ]
    .iter()
    .filter(|(n, _)| *n > 0)
    .map(|(n, what)| format!("{n} {what}"))
    .collect();
    if !counts.is_empty() {
        say!("sds: {}; see the report", counts.join(", "));
    }
    Ok(exit::ROUTE_PROBLEMS)
}

/// The rerun files a run writes (`--rerun-list`, `--rerun-xml`): where the user asked for them.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct RerunArgs<'a> {
    /// `--rerun-list FILE`.
    pub list: Option<&'a std::path::Path>,
    /// `--rerun-xml FILE`.
    pub xml: Option<&'a std::path::Path>,
    /// The route XML the routes come from (`--routes`).
    pub routes: Option<&'a std::path::Path>,
    /// `--rerun-timeouts`.
    pub timeouts: bool,
}

impl<'a> RerunArgs<'a> {
    fn of(args: &'a ScoreArgs) -> Self {
        RerunArgs {
            list: args.rerun_list.as_deref(),
            xml: args.rerun_xml.as_deref(),
            routes: args.run.routes.as_deref(),
            timeouts: args.rerun_timeouts,
        }
    }

    /// The paths asked for, each with its option's name.
    fn paths(&self) -> Vec<(&'static str, &'a std::path::Path)> {
        [("--rerun-list", self.list), ("--rerun-xml", self.xml)]
            .into_iter()
            .filter_map(|(o, p)| p.map(|p| (o, p)))
            .collect()
    }

    /// Before any work: no other output of the run has the path (`-o`, the other rerun file,
    /// a table or figure), and its folder exists (or is one the run creates: `dirs`) and the
    /// path is not a folder or device.
    pub fn check(
        &self,
        out: Option<&std::path::Path>,
        others: &[(&str, Vec<std::path::PathBuf>)],
        dirs: &[&std::path::Path],
    ) -> Result<()> {
        let paths = self.paths();
        for (i, (option, p)) in paths.iter().enumerate() {
            if let Some(out) = out {
                output::refuse_clash(out, &[p.to_path_buf()], option_file(option))?;
            }
            for (_, q) in &paths[i + 1..] {
                output::refuse_named_clash(p, option, &[q.to_path_buf()], "the other rerun file")?;
            }
            for (what, files) in others {
                output::refuse_named_clash(p, option, files, what)?;
            }
            let made = p.parent().is_some_and(|d| {
                dirs.iter()
                    .any(|m| output::refuse_clash(d, &[m.to_path_buf()], "").is_err())
            });
            if !made {
                output::check_folder(p).map_err(|e| {
                    output::BadOutputPath(format!("{option} {}: {}", p.display(), e.0))
                })?;
            }
        }
        Ok(())
    }

    /// The files' bytes, with the warnings to print (assembled by the library:
    /// `app::run::rerun::rerun_files`).
    fn files(&self, report: &monitor_host::Report) -> Result<RerunFiles> {
        // The route XML is read only when its restriction is asked for.
        let xml = self.xml.and(self.routes);
        let made = monitor_host::rerun_files(report, self.timeouts, xml)?;
        let mut out = RerunFiles {
            routes: made.list.routes.len(),
            warnings: made.warnings,
            ..RerunFiles::default()
        };
        if let Some(p) = self.list {
            out.files
                .push((p.to_path_buf(), made.list.text().into_bytes()));
        }
        if let (Some(p), Some(text)) = (self.xml, made.xml) {
            out.files.push((p.to_path_buf(), text));
        }
        Ok(out)
    }
}

/// The option's file, as a clash names it.
fn option_file(option: &str) -> &'static str {
    if option == "--rerun-xml" {
        "the rerun route XML"
    } else {
        "the rerun list"
    }
}

/// The rerun files of a run, ready to be placed with the rest of its output.
#[derive(Debug, Default)]
pub(crate) struct RerunFiles {
    /// Each file and its bytes.
    files: Vec<(std::path::PathBuf, Vec<u8>)>,
    /// Routes to run again.
    routes: usize,
    /// Printed once the run is written.
    warnings: Vec<String>,
}

impl RerunFiles {
    /// Places each file (inside the run's output unit: rolled back with the rest).
    fn place(&self, inputs: &[std::path::PathBuf]) -> Result<()> {
        for (p, bytes) in &self.files {
            output::place_named(p, bytes, inputs)?;
        }
        Ok(())
    }

    /// What was written, once the unit is committed.
    fn tell(&self) {
        for w in &self.warnings {
            say!("sds: warning: {w}");
        }
        for (p, _) in &self.files {
            say!(
                "sds: wrote {} route(s) to run again to {}",
                self.routes,
                p.display()
            );
        }
    }
}

/// An `-o` among the figures or the long tables is a usage error before any work (`sds score`
/// and `sds watch`; the traces' names are known once the run is scored, see [`write_all`]).
fn refuse_output_clashes(args: &ScoreArgs) -> Result<()> {
    let named = |dir: &Option<std::path::PathBuf>, names: &[&str]| -> Vec<std::path::PathBuf> {
        dir.iter()
            .flat_map(|d| names.iter().map(move |n| d.join(n)))
            .collect()
    };
    let dirs: Vec<&std::path::Path> = [&args.figures, &args.tables, &args.traces]
        .into_iter()
        .flatten()
        .map(std::path::PathBuf::as_path)
        .collect();
    RerunArgs::of(args).check(
        args.output.as_deref(),
        &[
            ("a figure", named(&args.figures, &output::FIGURE_NAMES)),
            ("a table", named(&args.tables, &long_tables::TABLE_NAMES)),
        ],
        &dirs,
    )?;
    if let (Some(out), Some(dir)) = (&args.output, &args.figures) {
        let figures: Vec<_> = output::FIGURE_NAMES.iter().map(|n| dir.join(n)).collect();
        output::refuse_clash(out, &figures, "a figure")?;
    }
    if let (Some(out), Some(dir)) = (&args.output, &args.tables) {
        let tables: Vec<_> = long_tables::TABLE_NAMES
            .iter()
            .map(|n| dir.join(n))
            .collect();
        output::refuse_clash(out, &tables, "a table")?;
    }
    Ok(())
}

/// Writes the traces, the figures, the long tables, the rerun files and then the report (`write_report`) of
/// `sds score` and of `sds watch`'s final round, all or nothing: a file that cannot be written
/// (or Ctrl-C) stops the run (exit 1, "no report") with every file this run wrote removed and
/// every file it replaced put back (`output::roll_back`). The rerun list and route XML are
/// written inside the same unit, before the report.
fn write_all(
    args: &ScoreArgs,
    report: &monitor_host::Report,
    inputs_read: &[std::path::PathBuf],
    write_report: impl FnOnce() -> Result<()>,
) -> Result<()> {
    if let Some(dir) = &args.traces {
        let traces = output::trace_paths(dir, report);
        if let Some(out) = &args.output {
            output::refuse_clash(out, &traces, "a trace")?;
        }
        RerunArgs::of(args).check(None, &[("a trace", traces)], &[dir])?;
    }
    let rerun = RerunArgs::of(args).files(report)?;
    let tables = match &args.tables {
        Some(_) => Some(request(args)?.long_tables(report).map_err(failed)?),
        None => None,
    };
    let written = (|| -> Result<_> {
        let traces = match &args.traces {
            Some(dir) => Some((dir, output::place_traces(dir, report, inputs_read)?)),
            None => None,
        };
        let figures = match &args.figures {
            Some(dir) => Some((dir, output::place_figures(dir, report, inputs_read)?)),
            None => None,
        };
        let tables = match (&args.tables, tables) {
            (Some(dir), Some(files)) => Some((dir, output::place_tables(dir, files, inputs_read)?)),
            _ => None,
        };
        rerun.place(inputs_read)?;
        write_report()?;
        Ok((traces, figures, tables))
    })();
    let (traces, figures, tables) = match written {
        Ok(w) => {
            output::commit();
            w
        }
        Err(e) => {
            output::roll_back();
            return Err(e);
        }
    };
    if let Some((dir, n)) = traces {
        say!("sds: wrote {n} collision trace(s) to {}", dir.display());
    }
    if let Some((dir, names)) = figures {
        say!("sds: wrote {} to {}", names.join(", "), dir.display());
    }
    if let Some((dir, ())) = tables {
        say!("sds: wrote the long tables to {}", dir.display());
    }
    rerun.tell();
    Ok(())
}
