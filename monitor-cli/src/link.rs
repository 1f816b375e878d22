//! `sds link` (the doer: plays a run to a checker) and `sds checker` (the checker on the host).

use std::path::PathBuf;

use anyhow::Result;
use monitor_host::input::duplicates::DuplicatePolicy;
use monitor_host::live_link::{Inject, Pace, Target};
use monitor_host::SettingsError;
use monitor_host::{link_config, LinkError, LinkRequest};

use crate::args::RunArgs;
use crate::output::write_output;

/// Arguments of `sds link`.
#[derive(Debug, clap::Args)]
pub struct LinkArgs {
    /// Results (as for `score`).
    #[arg(long, required_unless_present = "mcap", conflicts_with = "mcap")]
    pub results: Vec<PathBuf>,
    /// Telemetry root.
    #[arg(long)]
    pub telemetry: Option<PathBuf>,
    /// Vehicle logs instead of results (as for `score`).
    #[arg(long, value_name = "FILE")]
    pub mcap: Vec<PathBuf>,
    /// A vehicle log's topic, `NAME=TOPIC` (as for `score`).
    #[arg(long = "topic", value_name = "NAME=TOPIC", requires = "mcap")]
    pub topics: Vec<String>,
    /// The options of `score` (profile, maps, `--set`; `--set link.max_delta=N`,
    /// `link.timeout=N`, `link.window=N`, `link.max_errors=N` must match the checker's).
    #[command(flatten)]
    pub run: RunArgs,
    /// Which copy of a duplicated route id to play (as for `score`).
    #[arg(long, value_parser = crate::args::named(DuplicatePolicy::ALL, DuplicatePolicy::name))]
    pub duplicates: Option<DuplicatePolicy>,
    /// The checker: `serial:DEVICE[@BAUD]`, `tcp:HOST:PORT` or `exec:COMMAND`.
    #[arg(long, value_name = "TARGET")]
    pub to: String,
    /// `fast` (default): as fast as the checker reads; `realtime`: one frame per period.
    #[arg(long, value_parser = crate::args::named(Pace::ALL, Pace::name), default_value = "fast")]
    pub pace: Pace,
    /// Faults on the bytes the checker receives:
    /// `drop=P,corrupt=P,duplicate=P,reorder=P,stall=SECONDS,seed=N`.
    #[arg(long, value_name = "FAULTS")]
    pub inject: Option<String>,
    /// Copy every byte written to the checker into DIR/sent.bin and every byte read into
    /// DIR/received.bin.
    #[arg(long, value_name = "DIR")]
    pub tap: Option<PathBuf>,
    /// Write the report here instead of standard output.
    #[arg(short = 'o', long)]
    pub output: Option<PathBuf>,
}

/// Arguments of `sds checker`.
#[derive(Debug, clap::Args)]
pub struct CheckerArgs {
    /// Link settings: `link.max_delta=N` (3), `link.timeout=N` frame periods (3),
    /// `link.window=N` (20), `link.max_errors=N` (2).
    #[arg(long = "set", value_name = "NAME=VALUE")]
    pub set: Vec<String>,
}

/// `sds link`: exit 0 when every route was equal, 3 otherwise.
pub fn link(args: &LinkArgs) -> Result<i32> {
    // The `link.*` overrides stay in the settings: the request reads them (link_config).
    let settings = args.run.request(args.duplicates, None)?;
    let target: Target = args.to.parse().map_err(|_| SettingsError::Value {
        name: "--to",
        expected: "serial:DEVICE[@BAUD], tcp:HOST:PORT or exec:COMMAND".into(),
        value: args.to.clone(),
    })?;
    let given = args.inject.as_deref().unwrap_or("");
    let inject: Inject =
        given
            .parse()
            .map_err(
                |e: monitor_host::live_link::inject::InjectError| SettingsError::Value {
                    name: "--inject",
                    expected: e.to_string(),
                    value: given.to_string(),
                },
            )?;
    let request = LinkRequest {
        inputs: monitor_host::Inputs {
            results: args.results.clone(),
            telemetry: args.telemetry.clone(),
            route_xml: args.run.routes.clone(),
            maps: args.run.maps.clone(),
        },
        mcap: args.mcap.clone(),
        topics: args.topics.clone(),
        settings,
        target,
        pace: args.pace,
        inject,
        tap: args.tap.clone(),
    };
    let report = request.run().map_err(|e| match e {
        LinkError::Settings(e) => anyhow::Error::new(e),
        LinkError::Run(e) => anyhow::Error::new(e),
        LinkError::Request(e) => anyhow::Error::new(e),
        other => anyhow::Error::new(other),
    })?;
    let text = serde_json::to_string_pretty(&report)? + "\n";
    write_output(args.output.as_deref(), text.as_bytes(), &args.results)?;
    say!(
        "sds link: {} of {} routes equal to the replay over the accepted frames",
        report.summary.equal_routes,
        report.summary.routes
    );
    Ok(if report.all_equal() { 0 } else { 3 })
}

/// `sds checker`: the checker on standard input and output, until the input ends.
pub fn checker(args: &CheckerArgs) -> Result<i32> {
    let pairs = crate::args::overrides(&args.set)?;
    let (link, rest) = link_config(&pairs)?;
    if let Some((n, v)) = rest.first() {
        anyhow::bail!(SettingsError::Value {
            name: "--set",
            expected: "link.max_delta, link.timeout, link.window or link.max_errors".into(),
            value: format!("{n}={v}"),
        });
    }
    monitor_host::live_link::host_checker::run(std::io::stdin(), std::io::stdout().lock(), link)?;
    Ok(0)
}
