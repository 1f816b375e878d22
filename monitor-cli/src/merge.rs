//! `sds merge PART...` (docs/SCORE.md §13.2): the library's [`MergeRequest`], rendered as
//! `sds score` renders its report.

use anyhow::Result;

use super::args::MergeArgs;
use super::output::write_output_with;
use super::RerunArgs;
use monitor_host::input::duplicates::DuplicatePolicy;
use monitor_host::report::long_tables;
use monitor_host::report::render::{self, RenderOptions};
use monitor_host::MergeRequest;

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
    let tables_named: Vec<_> = args
        .tables
        .iter()
        .flat_map(|dir| long_tables::TABLE_NAMES.iter().map(move |n| dir.join(n)))
        .collect();
    if let Some(out) = &args.output {
        super::output::refuse_clash(out, &tables_named, "a table")?;
    }
    let rerun = RerunArgs {
        list: args.rerun_list.as_deref(),
        xml: args.rerun_xml.as_deref(),
        routes: args.routes.as_deref(),
        timeouts: args.rerun_timeouts,
    };
    let dirs: Vec<&std::path::Path> = args.tables.iter().map(|d| d.as_path()).collect();
    rerun.check(args.output.as_deref(), &[("a table", tables_named)], &dirs)?;
    let report = MergeRequest {
        parts: args.parts.clone(),
        duplicates: args.duplicates.unwrap_or(DuplicatePolicy::Error),
        host,
        // The table formats break down by scenario, as `sds score` does.
        by_scenario: args.format.style().is_some(),
    }
    .merge()?;
    for w in &report.warnings {
        say!("sds: {}", super::spelling::line(w));
    }
    // Rendered as it is written (below): a merge of 220,000 rows is never held twice, as rows
    // and as JSON text.
    let options = RenderOptions {
        name: render::run_name(&args.parts),
        ..RenderOptions::default()
    };
    // The long tables, then the report, all or nothing (as `sds score`).
    let tables = match &args.tables {
        Some(dir) => Some((
            dir,
            MergeRequest::long_tables(&report).map_err(anyhow::Error::msg)?,
        )),
        None => None,
    };
    if let Some(xml) = &args.routes {
        monitor_host::merge::check_route_xml(&report, xml)?;
    }
    let rerun = rerun.files(&report)?;
    let written = (|| -> Result<()> {
        if let Some((dir, files)) = tables.clone() {
            super::output::place_tables(dir, files, &report.files_read)?;
        }
        rerun.place(&report.files_read)?;
        write_output_with(args.output.as_deref(), &report.files_read, &|w| {
            render::write(&report, args.format, &options, w)
        })
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
    rerun.tell();
    say!(
        "sds: merged {} part(s): {} routes ({} found, {} missing)",
        args.parts.len(),
        report.summary.routes,
        report.summary.routes_found,
        report.summary.missing
    );
    Ok(if report.has_problems() { 3 } else { 0 })
}
