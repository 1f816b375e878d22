//! The command line's arguments (clap).

use std::path::PathBuf;

use clap::{Parser, Subcommand};

use monitor_core::Profile;
use monitor_host::aggregate::groups::GroupBy;
use monitor_host::demo::LargeLayout;
use monitor_host::input::duplicates::DuplicatePolicy;
use monitor_host::input::route_set::RouteSubset;
use monitor_host::settings::{AbilityRule, LateralReference, SettingsError};
use monitor_host::RunSettings;

/// `sds`: the SafeDriving Score of Bench2Drive runs.
#[derive(Debug, Parser)]
#[command(name = "sds", version, about, long_about = None)]
pub struct Cli {
    /// The command.
    #[command(subcommand)]
    pub command: Command,
}

/// Report formats: the library's (`report::render::Format`), named there once.
pub use monitor_host::report::render::Format;

/// A clap parser whose choices are a library enum's names (`named_enum!`, or the core's
/// `Profile`): the library spells each value once; the command line mirrors none.
pub fn named<T: Copy + Send + Sync + 'static>(
    all: &'static [T],
    name: fn(T) -> &'static str,
) -> impl clap::builder::TypedValueParser<Value = T> {
    described(all, name, |_| None)
}

/// [`named`] with a help line for each value (`--help` lists them), e.g. `--format`'s.
pub fn described<T: Copy + Send + Sync + 'static>(
    all: &'static [T],
    name: fn(T) -> &'static str,
    help: fn(T) -> Option<&'static str>,
) -> impl clap::builder::TypedValueParser<Value = T> {
    use clap::builder::{PossibleValue, TypedValueParser as _};
    clap::builder::PossibleValuesParser::new(all.iter().map(|v| {
        let value = PossibleValue::new(name(*v));
        match help(*v) {
            Some(h) => value.help(h),
            None => value,
        }
    }))
    .map(move |s| {
        *all.iter()
            .find(|v| name(**v) == s)
            .expect("clap checked the name against these values")
    })
}

/// The parser of `--format`: the library's formats, each with its help line.
fn formats() -> impl clap::builder::TypedValueParser<Value = Format> {
    described(Format::ALL, Format::name, |f| Some(f.help()))
}

/// The options `sds score` and `sds compare` share, defined once; [`RunArgs::request`] maps
/// them to the library's [`RunSettings`], as the Python `sds.score` does.
#[derive(Debug, clap::Args)]
pub struct RunArgs {
    /// Bench2Drive route XML: the lateral reference, the route set (its routes without a
    /// record are reported as missing and count as 0 / failed; N defaults to its size) and the
    /// scenario types of the ability rates. `sds compare`: shared by every run.
    #[arg(long)]
    pub routes: Option<PathBuf>,
    /// Folder of the towns' OpenDRIVE maps (`Town04.xodr`, ... or a CARLA install's Maps).
    #[arg(long)]
    pub maps: Option<PathBuf>,
    /// Comfort profile: `physical` (physical units, default), `b2d-legacy` (Bench2Drive's
    /// published smoothness, bugs included) or `autoware` (Autoware's planning envelope:
    /// passenger comfort on a vehicle, docs/SCORE.md §2.4).
    #[arg(long, value_parser = named(&Profile::ALL, Profile::name), default_value = "physical")]
    pub profile: Profile,
    /// Benchmark size N (missing routes count as 0 / failed), e.g. 220.
    #[arg(long)]
    pub expected_routes: Option<usize>,
    /// Score routes without telemetry without telemetry terms instead of failing them.
    #[arg(long)]
    pub allow_missing_telemetry: bool,
    /// Override a setting, e.g. `--set slack=0.9 --set bounds.yaw_rate=1.0 --set gap_max=6`.
    /// Names are those of the report's `config` block.
    #[arg(long = "set", value_name = "NAME=VALUE")]
    pub set: Vec<String>,
    /// Worker threads (default: all cores; never more than routes, at most 256).
    #[arg(long)]
    pub jobs: Option<usize>,
    /// Also score every route under these protocols (docs/PROTOCOLS.md): comma-separated ids of
    /// `b2d`, `lb2.0`, `lb2.1`, `lead-nds`, `f2d`, or `all` (setting `protocols`). The recorded
    /// events under other arithmetic, not a re-run: see docs/PROTOCOLS.md.
    #[arg(long = "protocol", value_name = "LIST|all")]
    pub protocol: Option<String>,
    /// Bench2Drive's Traffic_Signs counting rule (docs/SCORE.md §10.1): `b2d-0.0.4` (default) or
    /// `b2d-0.0.3`, the rule of the table most papers cite (every Traffic_Signs route counted
    /// twice). The same as `--set ability_rule=RULE`.
    #[arg(long = "ability-rule", value_name = "RULE",
          value_parser = clap::builder::PossibleValuesParser::new(AbilityRule::NAMES))]
    pub ability_rule: Option<String>,
    /// What the lateral error is measured against (docs/SCORE.md §3): `route` (the route
    /// polyline, its junction gaps filled by the map; default) or `lane` (the nearest driving
    /// lane of the map; a town without a map falls back to the route, with a warning). The same
    /// as `--set lateral_reference=...`.
    #[arg(long, value_parser = named(LateralReference::ALL, LateralReference::name))]
    pub lateral_reference: Option<LateralReference>,
}

impl RunArgs {
    /// The library's [`RunSettings`]: these options, the duplicate policy and route subset
    /// (`sds score` and `sds watch` only), and `--set` split into names and values.
    ///
    /// # Errors
    /// [`SettingsError::Syntax`]: a `--set` without `=`.
    pub fn request(
        &self,
        duplicates: Option<DuplicatePolicy>,
        route_subset: Option<RouteSubset>,
    ) -> Result<RunSettings, SettingsError> {
        let overrides = overrides(&self.set)?;
        Ok(RunSettings {
            profile: self.profile,
            expected_routes: self.expected_routes,
            duplicates,
            allow_missing_telemetry: self.allow_missing_telemetry,
            jobs: self.jobs,
            route_subset,
            // One list, as Python passes it (joined again with commas: the text given).
            protocols: self
                .protocol
                .as_ref()
                .map(|l| l.split(',').map(str::to_string).collect()),
            ability_rule: self.ability_rule.clone(),
            lateral_reference: self.lateral_reference,
            overrides,
        })
    }
}

/// `--set NAME=VALUE` options as `(name, value)` pairs.
///
/// # Errors
/// [`SettingsError::Syntax`]: a `--set` without `=`.
pub fn overrides(set: &[String]) -> Result<Vec<(String, String)>, SettingsError> {
    set.iter()
        .map(|s| {
            s.split_once('=')
                .map(|(n, v)| (n.to_string(), v.to_string()))
                .ok_or_else(|| SettingsError::Syntax(s.clone()))
        })
        .collect()
}

/// Arguments of `sds score`.
#[derive(Debug, clap::Args)]
pub struct ScoreArgs {
    /// Results: a raw evaluator file, a merged file, or a directory of per-route files.
    /// Repeat to read several: inputs in the order given, a directory's files in byte-wise
    /// path order, a file's records in order.
    #[arg(long, required_unless_present = "mcap", conflicts_with = "mcap")]
    pub results: Vec<PathBuf>,
    /// Telemetry root holding `<save_name>/metric_info.json`.
    #[arg(long)]
    pub telemetry: Option<PathBuf>,
    /// A vehicle log instead of results (docs/SCORE.md §2.4): an MCAP file of ROS 2 messages, or a
    /// rosbag2 folder of them; each log is one route named by its file stem. Repeatable.
    #[arg(long, value_name = "FILE")]
    pub mcap: Vec<PathBuf>,
    /// The topic of a vehicle log's signal: `pose=/odom` (Odometry or PoseStamped),
    /// `imu=/imu` (Imu), `event=TOPIC` (any message: a collision or emergency event),
    /// `path=TOPIC` (Path: the lateral reference). Repeatable; defaults `pose=/odom`, `imu=/imu`.
    #[arg(long = "topic", value_name = "NAME=TOPIC", requires = "mcap")]
    pub topics: Vec<String>,
    /// The options `sds compare` shares.
    #[command(flatten)]
    pub run: RunArgs,
    /// When two records share a route id: `error` (score nothing, name them), keep the
    /// `first` or `last` copy in input order, the `newest` run (latest `save_name` time stamp),
    /// or score `all` copies. Default: error (or
    /// `--set duplicates=...`).
    #[arg(long, value_parser = named(DuplicatePolicy::ALL, DuplicatePolicy::name))]
    pub duplicates: Option<DuplicatePolicy>,
    /// Which routes of `--routes` make the route set: `all` (default: a route without a record
    /// counts as 0) or those `found` with a record (a debug run over part of the XML). Also
    /// `--set route_subset=...`.
    #[arg(long, value_parser = named(RouteSubset::ALL, RouteSubset::name))]
    pub route_subset: Option<RouteSubset>,
    /// Output format.
    #[arg(long, value_parser = formats(), default_value = "json")]
    pub format: Format,
    /// Write the report here (atomically) instead of standard output.
    #[arg(short = 'o', long)]
    pub output: Option<PathBuf>,
    /// Break the routes down by this (the report's `groups`; the tables default to scenario).
    #[arg(long, value_parser = named(GroupBy::ALL, GroupBy::name))]
    pub group_by: Option<GroupBy>,
    /// Scenario type -> family label(s): a JSON object whose values are a label or a list of
    /// labels, or CSV `type,label` lines.
    #[arg(long)]
    pub families: Option<PathBuf>,
    /// Weather id -> label(s): a JSON object, CSV `id,label` lines, or Bench2Drive's
    /// `weather.xml` (labels from its preset names).
    #[arg(long)]
    pub weathers: Option<PathBuf>,
    /// Route id -> label(s), for `--group-by route` (a difficulty or train/test split, ...):
    /// keys `1711` (the XML route id: every repetition), `RouteScenario_1711` or
    /// `RouteScenario_1711_rep0` (one repetition; the most specific key wins); a JSON object
    /// whose values are a label or a list of labels, or CSV / TSV `id,label` lines.
    #[arg(long, value_name = "FILE")]
    pub labels: Option<PathBuf>,
    /// More infraction lists for the per-weather table (e.g. `collisions_vehicle`); repeatable.
    #[arg(long = "infraction", value_name = "LIST")]
    pub infractions: Vec<String>,
    /// Also write every aligned collision's trace (docs/SCORE.md §14.4) into DIR, as
    /// `<route_id>_collision<i>.csv` and `.svg` (the paper's Figure 2).
    #[arg(long, value_name = "DIR")]
    pub traces: Option<PathBuf>,
    /// Also write the run's pictures into DIR as SVG: `decomposition.svg` (from DS to SDS, step
    /// by step) and `routes.svg` (DS and DS_safe per route, sorted), as the HTML page shows them.
    #[arg(long, value_name = "DIR")]
    pub figures: Option<PathBuf>,
    /// Also write the routes to run again into FILE: one route XML id per line with the reason
    /// after a tab (missing, simulation-crashed, agent-crashed, agent-setup, failed, invalid;
    /// Bench2Drive's resume rule), for the Leaderboard's `--routes-subset`. `sds watch` writes
    /// it from its final report, when it stops.
    #[arg(long, value_name = "FILE")]
    pub rerun_list: Option<PathBuf>,
    /// Also write the route XML of `--routes` restricted to the routes to run again into FILE
    /// (each `<route>` element as in the input), for Bench2Drive's `run_evaluation.sh`.
    #[arg(long, value_name = "FILE", requires = "routes")]
    pub rerun_xml: Option<PathBuf>,
    /// List the routes that ran out of their tick budget (`Failed - TickRuntime`: the agent's
    /// outcome, not a crash) among the routes to run again, as `timeout`.
    #[arg(long)]
    pub rerun_timeouts: bool,
    /// Also write the long tables into DIR (docs/TABLES-SCHEMA.md): `routes.csv` (one row per route,
    /// every field of the JSON report's route), `events.csv` (one row per event) and
    /// `frames.csv` (one row per frame of each route with telemetry, as `sds frames` prints
    /// it); columns in docs/TABLES-SCHEMA.md.
    #[arg(long, value_name = "DIR")]
    pub tables: Option<PathBuf>,
}

/// Arguments of `sds compare` (docs/SCORE.md §10.3).
#[derive(Debug, clap::Args)]
pub struct CompareArgs {
    /// Runs: `NAME=RESULTS[:TELEMETRY]`, or `RESULTS` (named by its folder or file name).
    /// RESULTS is a results file or folder; TELEMETRY the run's telemetry root (default: the
    /// results file's folder, or `--telemetry-of NAME=DIR`). The first model is the baseline.
    #[arg(required = true, value_name = "RUN")]
    pub runs: Vec<String>,
    /// The telemetry root of run NAME (instead of `:TELEMETRY`); repeatable.
    #[arg(long, value_name = "NAME=DIR")]
    pub telemetry_of: Vec<String>,
    /// Runs that are seeds of one model: `MODEL=RUN,RUN,...` (run names); repeatable. Runs are
    /// grouped only here (never by their names); every other run is a model of its own.
    #[arg(long, value_name = "MODEL=RUNS")]
    pub seeds: Vec<String>,
    /// The baseline model (default: the first).
    #[arg(long, value_name = "MODEL")]
    pub baseline: Option<String>,
    /// Compare over the route keys every run holds (with a warning) instead of refusing runs
    /// whose route sets differ.
    #[arg(long)]
    pub common_routes: bool,
    /// Exit 5 after writing the report when a model is `worse` than the baseline on one of
    /// these metrics, or could not be compared on it (`no data`: n = 0) (`ds`, `success`,
    /// `ds_safe`, `comfort`, or `ds@<protocol>` for a protocol asked with `--protocol`, e.g.
    /// `ds@lb2.1`; comma-separated).
    #[arg(long, value_name = "METRICS", value_delimiter = ',')]
    pub fail_if_worse: Vec<String>,
    /// Bootstrap resamples B: 1000 to 1000000, and n × B at most 250 million per model and
    /// metric (n routes compared).
    #[arg(long, default_value_t = 10_000)]
    pub bootstrap_samples: usize,
    /// Seed of the bootstrap's SplitMix64 generator.
    #[arg(long, default_value_t = 0)]
    pub bootstrap_seed: u64,
    /// Rank the models: each one's rank with a 95 % bootstrap interval and the share of
    /// resamples where it is best (`p_best`).
    #[arg(long)]
    pub rank: bool,
    /// `repro.halfwidth`: the half-width, in DS points, of the 95 % interval of a model's mean
    /// DS that `seeds_needed` sizes.
    #[arg(long, value_name = "DS", default_value_t = 1.0)]
    pub repro_halfwidth: f64,
    /// Which routes of `--routes` make each run's route set: `all` (default: a route without a
    /// record counts as 0) or those `found` with a record, as `sds score --route-subset`. Also
    /// `--set route_subset=...`.
    #[arg(long, value_parser = named(RouteSubset::ALL, RouteSubset::name))]
    pub route_subset: Option<RouteSubset>,
    /// Score every model at every point of a grid of settings: `NAME=V1,V2,...` (repeatable;
    /// the grid is the product of the lists, at most 64 points; NAME a setting that changes a
    /// route's figures). Adds each model's DS_safe, comfort, SDS and rank at every point and
    /// whether each pair's order holds (docs/USAGE.md, "Do the conclusions survive?").
    #[arg(long, value_name = "NAME=V1,V2,...")]
    pub sweep: Vec<String>,
    /// The options `sds score` shares (each run scored with them).
    #[command(flatten)]
    pub run: RunArgs,
    /// Output format (`csv` is not available here).
    #[arg(long, value_parser = formats(), default_value = "table")]
    pub format: Format,
    /// Write here (atomically) instead of standard output.
    #[arg(short = 'o', long)]
    pub output: Option<PathBuf>,
    /// Also write the long tables of every run into DIR (docs/TABLES-SCHEMA.md): `routes.csv` and
    /// `events.csv`, as `sds score --tables` writes them, each row led by its `run` and `model`.
    #[arg(long, value_name = "DIR")]
    pub tables: Option<PathBuf>,
}

/// Subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Score a run: every route through the streaming monitor, then the report.
    Score(ScoreArgs),
    /// Compare runs against a baseline: paired deltas per route with bootstrap intervals,
    /// verdicts, flips, and a regression gate (`--fail-if-worse`, exit 5).
    Compare(CompareArgs),
    /// Score an evaluation while it runs: the inputs of `score`, read again every `--interval`
    /// seconds, the report (`-o`) rewritten after every round, one status line per round.
    Watch(WatchArgs),
    /// Merge the JSON reports of `sds score` scored where the files are (one per shard, node
    /// or GPU) into the report `sds score` over all their inputs would write (docs/SCORE.md §13.2).
    Merge(MergeArgs),
    /// Play a run (or vehicle logs) to a checker over a byte stream and check that its events
    /// equal the replay of the frames it accepted (exit 3 when a route's do not).
    Link(crate::link::LinkArgs),
    /// The checker on the host: the doer's messages on standard input, its answers on
    /// standard output.
    Checker(crate::link::CheckerArgs),
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
        /// Keys per frame of the large run's telemetry: `b2d` (Bench2Drive's six keys per
        /// frame, what its agents write) or `wide` (thirteen: the six plus velocity, speed,
        /// controls, gps, compass).
        #[arg(long, value_parser = named(LargeLayout::ALL, LargeLayout::name), default_value = "b2d")]
        layout: LargeLayout,
        /// Routes of the large run that collide (at frame 2,000).
        #[arg(long, default_value_t = 0)]
        large_collisions: usize,
        /// Overwrite an earlier run in DIR (its results.json, routes.xml, telemetry and maps;
        /// with --score also report.html and traces/).
        #[arg(long)]
        force: bool,
    },
    /// Print the monitor's input frames of one route as JSON lines (serde-json-core encoding),
    /// each with the host-side values behind it (`host`: step, reference, distance to it, slack,
    /// lane width). Takes every option of `score` that changes a frame.
    Frames(FramesArgs),
}

/// Arguments of `sds frames`.
#[derive(Debug, clap::Args)]
pub struct FramesArgs {
    /// Results file or directory (repeatable, as for `score`).
    #[arg(long, required_unless_present = "mcap", conflicts_with = "mcap")]
    pub results: Vec<PathBuf>,
    /// A vehicle log (MCAP file or rosbag2 folder) instead of results (docs/SCORE.md §2.4).
    #[arg(long, value_name = "FILE")]
    pub mcap: Option<PathBuf>,
    /// A vehicle log's topic, `NAME=TOPIC` (as for `score`).
    #[arg(long = "topic", value_name = "NAME=TOPIC", requires = "mcap")]
    pub topics: Vec<String>,
    /// Telemetry root.
    #[arg(long)]
    pub telemetry: Option<PathBuf>,
    /// The options of `score` (the route XML, the maps, the profile, `--set`, ...): one
    /// definition, so an option that changes a frame is read here as there.
    #[command(flatten)]
    pub run: RunArgs,
    /// Which copy of a duplicated route id to print (as for `score`).
    #[arg(long, value_parser = named(DuplicatePolicy::ALL, DuplicatePolicy::name))]
    pub duplicates: Option<DuplicatePolicy>,
    /// The route id (`RouteScenario_<id>_rep<k>`).
    #[arg(long, required_unless_present = "mcap")]
    pub route_id: Option<String>,
    /// Write here instead of standard output.
    #[arg(short = 'o', long)]
    pub output: Option<PathBuf>,
}

/// Arguments of `sds watch`.
#[derive(Debug, clap::Args)]
pub struct WatchArgs {
    /// The inputs and options of `sds score` (`-o` is required).
    #[command(flatten)]
    pub score: ScoreArgs,
    /// Seconds between rounds (fractions allowed; above 0, at most 86400).
    #[arg(long, default_value_t = 10.0, value_name = "SECONDS")]
    pub interval: f64,
    /// One round, then the final report.
    #[arg(long)]
    pub once: bool,
    /// Stop after this many seconds (with the final report; 0 to 31536000).
    #[arg(long, value_name = "SECONDS")]
    pub timeout: Option<f64>,
    /// Print each round's status as one JSON object per line (standard error) instead of text.
    #[arg(long)]
    pub status_json: bool,
    /// With several shard checkpoints: warn when a shard has written no record for longer than
    /// K times its median route time (its worker may have died).
    #[arg(long, value_name = "K", default_value_t = monitor_host::model::shard_stall::DEFAULT_FACTOR)]
    pub stall_factor: f64,
}

/// Arguments of `sds merge`.
#[derive(Debug, clap::Args)]
pub struct MergeArgs {
    /// The parts: JSON reports of `sds score` (each shard scored where its files are), all
    /// scored with the same settings and, with `--routes`, the same route XML.
    #[arg(required = true, value_name = "PART")]
    pub parts: Vec<PathBuf>,
    /// Output format (the formats of `sds score`).
    #[arg(long, value_parser = formats(), default_value = "json")]
    pub format: Format,
    /// Output file (default: standard output); never one of the parts.
    #[arg(short = 'o', long)]
    pub output: Option<PathBuf>,
    /// A route id with a record in two parts: `error` (default) names both parts; `first` /
    /// `last` keep the first / last part's record; `newest` the latest `save_name` time stamp
    /// (each row keeps its record's); `all` scores both. The merged `config.duplicates` states
    /// the rule applied.
    #[arg(long, value_parser = named(DuplicatePolicy::ALL, DuplicatePolicy::name))]
    pub duplicates: Option<DuplicatePolicy>,
    /// `provenance.host=false` leaves this machine's name out of the merged report (the
    /// scoring settings come from the parts).
    #[arg(long = "set", value_name = "NAME=VALUE")]
    pub set: Vec<String>,
    /// Also write the routes to run again into FILE (one route XML id per line, the reason
    /// after a tab).
    #[arg(long, value_name = "FILE")]
    pub rerun_list: Option<PathBuf>,
    /// Also write the route XML restricted to the routes to run again into FILE (needs
    /// `--routes`, the parts' own route XML: its sha256 is checked against theirs).
    #[arg(long, value_name = "FILE", requires = "routes")]
    pub rerun_xml: Option<PathBuf>,
    /// The route XML the parts were scored with, for `--rerun-xml`.
    #[arg(long, value_name = "FILE", requires = "rerun_xml")]
    pub routes: Option<PathBuf>,
    /// List the `Failed - TickRuntime` routes among the routes to run again, as `timeout`.
    #[arg(long)]
    pub rerun_timeouts: bool,
    /// Also write the long tables into DIR (`routes.csv`, `events.csv`, from the merged rows;
    /// no `frames.csv`: a merge reads no telemetry); columns in docs/TABLES-SCHEMA.md.
    #[arg(long, value_name = "DIR")]
    pub tables: Option<PathBuf>,
}
