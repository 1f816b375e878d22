//! `sds merge PART...` (spec v1.4 §13): the library's [`MergeRequest`], rendered as
//! `sds score` renders its report.

use std::path::PathBuf;

use anyhow::Result;

use super::args::{DuplicatesArg, Format};
use super::output::write_output;
use super::{style, write_rerun_list};
use crate::app::merged::MergeRequest;
use crate::input::duplicates::DuplicatePolicy;
use crate::report::table::{self, TableOptions};
use crate::report::{csv, html, json, long_tables};

/// Arguments of `sds merge`.
#[derive(Debug, clap::Args)]
pub struct MergeArgs {
    /// The parts: JSON reports of `sds score` (each shard scored where its files are), all
    /// scored with the same settings and, with `--routes`, the same route XML.
    #[arg(required = true, value_name = "PART")]
    pub parts: Vec<PathBuf>,
    /// Output format (the formats of `sds score`).
    #[arg(long, value_enum, default_value = "json")]
    pub format: Format,
    /// Output file (default: standard output); never one of the parts.
    #[arg(short = 'o', long)]
    pub output: Option<PathBuf>,
    /// A route id with a record in two parts: `error` (default) names both parts; `first` /
    /// `last` keep the first / last part's record; `all` scores both.
    #[arg(long, value_enum)]
    pub duplicates: Option<DuplicatesArg>,
    /// `provenance.host=false` leaves this machine's name out of the merged report (the
    /// scoring settings come from the parts).
    #[arg(long = "set", value_name = "NAME=VALUE")]
    pub set: Vec<String>,
    /// Also write the routes to run again into FILE (one route XML id per line, the reason
    /// after a tab).
    #[arg(long, value_name = "FILE")]
    pub rerun_list: Option<PathBuf>,
    /// Also write the long tables into DIR (`routes.csv`, `events.csv`, from the merged rows;
    /// no `frames.csv`: a merge reads no telemetry); columns in docs/TABLES-SCHEMA.md.
    #[arg(long, value_name = "DIR")]
    pub tables: Option<PathBuf>,
}

/// Runs `sds merge`: 0, or 3 when the merged report has a problem route (as `sds score`).
pub fn merge(args: &MergeArgs) -> Result<i32> {
    let mut host = true;
    for s in &args.set {
        match s.split_once('=') {
            Some(("provenance.host", v)) => {
                host = v.trim().parse::<bool>().map_err(|_| {
                    anyhow::anyhow!("--set provenance.host={v}: expected true or false")
                })?;
            }
            _ => anyhow::bail!(
                "--set {s}: sds merge takes only provenance.host; the scoring settings are the \
                 parts' (score every part with the same --set)"
            ),
        }
    }
    if let (Some(out), Some(dir)) = (&args.output, &args.tables) {
        let tables: Vec<_> = long_tables::TABLE_NAMES
            .iter()
            .map(|n| dir.join(n))
            .collect();
        super::output::refuse_clash(out, &tables, "a table")?;
    }
    let report = MergeRequest {
        parts: args.parts.clone(),
        duplicates: args
            .duplicates
            .map_or(DuplicatePolicy::Error, DuplicatesArg::policy),
        host,
        // The table formats break down by scenario, as `sds score` does.
        by_scenario: style(args.format).is_some(),
    }
    .merge()?;
    for w in &report.warnings {
        say!("sds: warning: {w}");
    }
    let options = TableOptions::default();
    let name = args
        .parts
        .iter()
        .map(|p| {
            p.file_name().map_or_else(
                || p.display().to_string(),
                |n| n.to_string_lossy().into_owned(),
            )
        })
        .collect::<Vec<_>>()
        .join(", ");
    let bytes = match (args.format, style(args.format)) {
        (Format::Json, _) => json::json(&report)?,
        (Format::Csv, _) => csv::groups_csv(&report).unwrap_or_else(|| csv::csv(&report)),
        (Format::Html, _) => html::page(&report, &options, &name).into_bytes(),
        (_, Some(style)) => {
            table::render(&table::report_tables(&report, &options), style).into_bytes()
        }
        (_, None) => anyhow::bail!("no renderer for {:?}", args.format),
    };
    // The long tables, then the report, all or nothing (as `sds score`). The merge reads no
    // telemetry, so there are no frames (the parts' `sds score --tables` wrote theirs).
    let tables = match &args.tables {
        Some(dir) => {
            let mut t = long_tables::long_tables(&report, &[]).map_err(anyhow::Error::msg)?;
            t.frames = None;
            Some((dir, t.files().map_err(anyhow::Error::msg)?))
        }
        None => None,
    };
    let written = (|| -> Result<()> {
        if let Some((dir, files)) = tables.clone() {
            super::output::place_tables(dir, files, &report.files_read)?;
        }
        write_output(args.output.as_deref(), &bytes, &report.files_read)
    })();
    match written {
        Ok(()) => super::output::commit(),
        Err(e) => {
            super::output::roll_back();
            return Err(e);
        }
    }
    if let Some((dir, _)) = &tables {
        say!(
            "sds: wrote the long tables to {} (routes, events; no frames: a merge reads no telemetry)",
            dir.display()
        );
    }
    if let Some(file) = &args.rerun_list {
        write_rerun_list(file, &report, &report.files_read)?;
    }
    say!(
        "sds: merged {} part(s): {} routes ({} found, {} missing)",
        args.parts.len(),
        report.summary.routes,
        report.summary.routes_found,
        report.summary.missing
    );
    Ok(if report.has_problems() { 3 } else { 0 })
}
