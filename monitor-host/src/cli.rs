//! The `sds` command line: `score`, `demo`, `frames`.
//!
//! Exit codes: 0 success; 1 an input could not be read or the output not written (no report);
//! 2 usage error; 3 the report was written but some route has a problem (missing or invalid
//! telemetry without `--allow-missing-telemetry`, an invalid record, or a streaming/batch
//! disagreement) — every such route is in the report with its state.

use std::collections::BTreeMap;
use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use clap::{Parser, Subcommand, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use rayon::prelude::*;

use crate::replay::{self, Options};
use crate::report::{self, GroupBy};
use crate::{demo, results, route};

/// Exit code: the report was written, but some route has a problem.
pub const EXIT_ROUTE_PROBLEMS: i32 = 3;

/// `sds`: the SafeDriving Score of Bench2Drive runs.
#[derive(Debug, Parser)]
#[command(name = "sds", version, about, long_about = None)]
pub struct Cli {
    /// The command.
    #[command(subcommand)]
    pub command: Command,
}

/// Report formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Format {
    /// The JSON report of spec section 10.
    Json,
    /// The paper's Table 1 row and a Table 2-style breakdown.
    Table,
    /// One line per route.
    Csv,
}

/// Comfort profiles.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ProfileArg {
    /// Physical units (default).
    Physical,
    /// Bench2Drive's published smoothness, bugs included.
    #[value(name = "b2d-legacy")]
    B2dLegacy,
}

/// Breakdown groups.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum GroupArg {
    /// Scenario type.
    Scenario,
    /// Scenario family (`--families`).
    Family,
    /// Town.
    Town,
    /// Weather (`--weathers`).
    Weather,
}

/// Arguments of `sds score`.
#[derive(Debug, clap::Args)]
pub struct ScoreArgs {
    /// Results: a raw evaluator file, a merged file, or a directory of per-route files.
    /// Repeat to read several.
    #[arg(long, required = true)]
    pub results: Vec<PathBuf>,
    /// Telemetry root holding `<save_name>/metric_info.json`.
    #[arg(long)]
    pub telemetry: Option<PathBuf>,
    /// Bench2Drive route XML (reference for the lateral error).
    #[arg(long)]
    pub routes: Option<PathBuf>,
    /// Comfort profile.
    #[arg(long, value_enum, default_value = "physical")]
    pub profile: ProfileArg,
    /// Benchmark size N (missing routes count as 0 / failed), e.g. 220.
    #[arg(long)]
    pub expected_routes: Option<usize>,
    /// Score routes without telemetry without telemetry terms instead of failing them.
    #[arg(long)]
    pub allow_missing_telemetry: bool,
    /// Output format.
    #[arg(long, value_enum, default_value = "json")]
    pub format: Format,
    /// Write the report here (atomically) instead of standard output.
    #[arg(short = 'o', long)]
    pub output: Option<PathBuf>,
    /// Group the table's breakdown by this.
    #[arg(long, value_enum, default_value = "scenario")]
    pub group_by: GroupArg,
    /// Scenario type -> family label (JSON object, or CSV `type,label` lines).
    #[arg(long)]
    pub families: Option<PathBuf>,
    /// Weather id -> label (JSON object, or CSV `id,label` lines).
    #[arg(long)]
    pub weathers: Option<PathBuf>,
    /// Override a setting, e.g. `--set slack=0.9 --set bounds.yaw_rate=1.0 --set gap_max=6`.
    /// Names are those of the report's `config` block.
    #[arg(long = "set", value_name = "NAME=VALUE")]
    pub set: Vec<String>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub jobs: Option<usize>,
}

/// Subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Score a run: every route through the streaming monitor, then the report.
    Score(ScoreArgs),
    /// Write the built-in demo run into DIR (and score it with --score).
    Demo {
        /// Output folder.
        dir: PathBuf,
        /// Score the demo afterwards and print the table.
        #[arg(long)]
        score: bool,
        /// Write a benchmark-sized run (220 routes x 4,000 frames) instead.
        #[arg(long)]
        large: bool,
        /// Routes of the large run.
        #[arg(long, default_value_t = 220)]
        large_routes: usize,
        /// Frames per route of the large run.
        #[arg(long, default_value_t = 4000)]
        large_frames: usize,
    },
    /// Print the monitor's input frames of one route as JSON lines (serde-json-core encoding).
    Frames {
        /// Results file or directory.
        #[arg(long)]
        results: PathBuf,
        /// Telemetry root.
        #[arg(long)]
        telemetry: Option<PathBuf>,
        /// Route XML.
        #[arg(long)]
        routes: Option<PathBuf>,
        /// The route id (`RouteScenario_<id>_rep<k>`).
        #[arg(long)]
        route_id: String,
        /// Write here instead of standard output.
        #[arg(short = 'o', long)]
        output: Option<PathBuf>,
    },
}

/// Runs the command line; returns the exit code.
pub fn main() -> i32 {
    let cli = Cli::parse();
    match run(cli) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("sds: error: {e:#}");
            1
        }
    }
}

/// Runs a parsed command; returns the exit code.
pub fn run(cli: Cli) -> Result<i32> {
    match cli.command {
        Command::Score(args) => score(&args),
        Command::Demo {
            dir,
            score: then_score,
            large,
            large_routes,
            large_frames,
        } => {
            let run = if large {
                demo::write_large(&dir, large_routes, large_frames)?
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
            let args = ScoreArgs {
                results: vec![run.results],
                telemetry: Some(run.telemetry),
                routes: Some(run.routes),
                profile: ProfileArg::Physical,
                expected_routes: None,
                allow_missing_telemetry: false,
                format: Format::Table,
                output: None,
                group_by: GroupArg::Scenario,
                families: None,
                weathers: None,
                set: vec![],
                jobs: None,
            };
            score(&args)
        }
        Command::Frames {
            results,
            telemetry: tel_root,
            routes,
            route_id,
            output,
        } => frames(
            &results,
            tel_root,
            routes.as_deref(),
            &route_id,
            output.as_deref(),
        ),
    }
}

/// Applies `--set name=value` overrides to the options through their JSON form.
pub fn apply_overrides(opts: &mut Options, sets: &[String]) -> Result<()> {
    if sets.is_empty() {
        return Ok(());
    }
    let mut core = serde_json::to_value(opts.config)?;
    for s in sets {
        let (name, value) = s
            .split_once('=')
            .with_context(|| format!("--set {s}: expected NAME=VALUE"))?;
        let parsed: serde_json::Value = serde_json::from_str(value)
            .unwrap_or_else(|_| serde_json::Value::String(value.to_string()));
        let host = |x: &mut f64| -> Result<()> {
            *x = parsed
                .as_f64()
                .with_context(|| format!("--set {s}: expected a number"))?;
            Ok(())
        };
        match name {
            "gap_max" => host(&mut opts.gap_max)?,
            "lookahead" => host(&mut opts.lookahead)?,
            "align_max_dist" => host(&mut opts.align_max_dist)?,
            "align_tie" => host(&mut opts.align_tie)?,
            _ => {
                let mut slot = &mut core;
                for part in name.split('.') {
                    slot = slot
                        .get_mut(part)
                        .with_context(|| format!("--set {s}: unknown setting {name}"))?;
                }
                if slot.is_object() {
                    bail!("--set {s}: {name} is a group; name one of its fields");
                }
                *slot = parsed;
            }
        }
    }
    opts.config = serde_json::from_value(core).context("--set: invalid value")?;
    opts.config
        .validate(monitor_core::DEFAULT_CAPACITY)
        .map_err(|e| anyhow::anyhow!("invalid configuration: {e}"))?;
    Ok(())
}

fn read_labels(path: &Path) -> Result<BTreeMap<String, String>> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    if text.trim_start().starts_with('{') {
        let map: BTreeMap<String, serde_json::Value> = serde_json::from_str(&text)
            .with_context(|| format!("{}: not a JSON object of labels", path.display()))?;
        return Ok(map
            .into_iter()
            .map(|(k, v)| {
                let label = v.as_str().map_or_else(|| v.to_string(), str::to_string);
                (k, label)
            })
            .collect());
    }
    let mut map = BTreeMap::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let (k, v) = line
            .split_once([',', '\t'])
            .with_context(|| format!("{}:{}: expected `key,label`", path.display(), i + 1))?;
        map.insert(k.trim().to_string(), v.trim().to_string());
    }
    Ok(map)
}

/// Writes `bytes` to `path` atomically (a temporary file in the same folder, then a rename),
/// or to standard output.
pub fn write_output(path: Option<&Path>, bytes: &[u8]) -> Result<()> {
    match path {
        None => {
            let mut out = std::io::stdout().lock();
            out.write_all(bytes)?;
            out.flush()?;
        }
        Some(p) => {
            let dir = p
                .parent()
                .filter(|d| !d.as_os_str().is_empty())
                .unwrap_or(Path::new("."));
            let mut tmp = tempfile::NamedTempFile::new_in(dir)
                .with_context(|| format!("cannot create a file in {}", dir.display()))?;
            tmp.write_all(bytes)?;
            tmp.as_file().sync_all()?;
            tmp.persist(p)
                .with_context(|| format!("cannot write {}", p.display()))?;
        }
    }
    Ok(())
}

fn score(args: &ScoreArgs) -> Result<i32> {
    let mut opts = Options {
        telemetry_root: args.telemetry.clone(),
        allow_missing_telemetry: args.allow_missing_telemetry,
        ..Options::default()
    };
    opts.config.profile = match args.profile {
        ProfileArg::Physical => monitor_core::Profile::Physical,
        ProfileArg::B2dLegacy => monitor_core::Profile::B2dLegacy,
    };
    apply_overrides(&mut opts, &args.set)?;

    let mut records = Vec::new();
    let mut warnings = Vec::new();
    for path in &args.results {
        let set = results::load(path)?;
        warnings.extend(set.warnings);
        records.extend(set.records);
        // A results file that cannot be read still appears, as an invalid entry: its routes
        // are unknown, but nothing found is silently lost.
        records.extend(set.broken_files.into_iter().map(|(source, reason)| {
            results::LoadedRecord {
                source,
                index: 0,
                records_in_file: 0,
                entry: Err(results::InvalidRecord {
                    route_id: None,
                    reason,
                }),
            }
        }));
    }
    let routes = match &args.routes {
        Some(p) => Some(route::load(p)?),
        None => None,
    };
    if let Some(n) = args.expected_routes {
        if n < records.len() {
            warnings.push(format!(
                "--expected-routes {n} is smaller than the {} routes found",
                records.len()
            ));
        }
    }

    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.jobs.unwrap_or(0))
        .build()?;
    let bar = ProgressBar::new(records.len() as u64);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} routes {elapsed_precise} eta {eta}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let outcomes: Vec<_> = pool.install(|| {
        records
            .par_iter()
            .map(|r| {
                let o = replay::replay(r, routes.as_ref(), &opts);
                bar.inc(1);
                o
            })
            .collect()
    });
    bar.finish_and_clear();

    let report = report::build(&outcomes, &opts, args.expected_routes, warnings);
    for w in &report.warnings {
        eprintln!("sds: warning: {w}");
    }
    for r in &report.routes {
        for w in &r.warnings {
            let id = r.route_id.as_deref().unwrap_or("<no route_id>");
            eprintln!("sds: warning: {id}: {w}");
        }
    }
    let bytes = match args.format {
        Format::Json => {
            let mut v = serde_json::to_vec_pretty(&report)?;
            v.push(b'\n');
            v
        }
        Format::Csv => report::csv(&report).into_bytes(),
        Format::Table => {
            let group = match args.group_by {
                GroupArg::Scenario => GroupBy::Scenario,
                GroupArg::Family => GroupBy::Family,
                GroupArg::Town => GroupBy::Town,
                GroupArg::Weather => GroupBy::Weather,
            };
            let labels = match (group, &args.families, &args.weathers) {
                (GroupBy::Family, Some(f), _) => read_labels(f)?,
                (GroupBy::Weather, _, Some(w)) => read_labels(w)?,
                _ => BTreeMap::new(),
            };
            report::table(&report, group, &labels).into_bytes()
        }
    };
    write_output(args.output.as_deref(), &bytes)?;

    let s = &report.summary;
    let mut problems = false;
    if report.routes.is_empty() {
        problems = true;
        eprintln!("sds: no route found in the results: nothing was scored");
    }
    for r in &report.routes {
        if r.state != "ok" && !(opts.allow_missing_telemetry && r.penalty_check.is_some()) {
            problems = true;
            eprintln!(
                "sds: {} ({}): {}",
                r.route_id.as_deref().unwrap_or("<no route_id>"),
                r.source,
                r.state
            );
        }
    }
    if !s.batch_disagreements.is_empty() {
        problems = true;
        eprintln!(
            "sds: streaming and batch disagree on {:?} (please report this bug)",
            s.batch_disagreements
        );
    }
    if problems {
        eprintln!(
            "sds: {} route(s) with telemetry problems, {} invalid record(s); see the report",
            s.telemetry_problems, s.invalid_records
        );
        return Ok(EXIT_ROUTE_PROBLEMS);
    }
    Ok(0)
}

fn frames(
    results_path: &Path,
    tel_root: Option<PathBuf>,
    routes: Option<&Path>,
    route_id: &str,
    output: Option<&Path>,
) -> Result<i32> {
    let set = results::load(results_path)?;
    let routes = routes.map(route::load).transpose()?;
    let loaded = set
        .records
        .iter()
        .find(|r| r.entry.as_ref().is_ok_and(|r| r.route_id == route_id))
        .with_context(|| format!("{}: no route {route_id}", results_path.display()))?;
    let Ok(record) = &loaded.entry else {
        bail!("{route_id}: invalid record");
    };
    let opts = Options {
        telemetry_root: tel_root,
        ..Options::default()
    };
    let mut warnings = Vec::new();
    let prepared = replay::load(loaded, record, routes.as_ref(), &opts, &mut warnings)
        .map_err(|state| anyhow::anyhow!("{route_id}: telemetry {state}"))?
        .prepared;
    for w in warnings {
        eprintln!("sds: warning: {route_id}: {w}");
    }
    let mut out = Vec::new();
    let mut buf = [0u8; 512];
    for f in &prepared.frames {
        let n = monitor_core::json::encode(f, &mut buf)
            .map_err(|e| anyhow::anyhow!("cannot encode a frame: {e}"))?;
        out.extend_from_slice(&buf[..n]);
        out.push(b'\n');
    }
    write_output(output, &out)?;
    Ok(0)
}
