//! Merging reports scored where the files are (docs/SCORE.md §13.2): each node scores its
//! shard with `sds score`; [`merge`] reads the parts' JSON reports back into the rows `sds
//! score` aggregated ([`Report::from_json`]: the types that wrote them) and builds the report with the same code
//! ([`crate::model::report::assemble_rows`]), so the merge equals `sds score` over the union
//! of the parts' inputs (every field but `inputs` and `warnings`), and a merge of merges equals
//! the merge of all parts.
//!
//! ```
//! use monitor_host::{demo, merge, report, score_run, Inputs, Settings};
//! use monitor_host::input::duplicates::DuplicatePolicy;
//!
//! let dir = tempfile::tempdir()?;
//! let run = demo::write(dir.path())?;
//! let inputs = Inputs { telemetry: Some(run.telemetry), route_xml: Some(run.routes),
//!                       ..Inputs::new([run.results]) };
//! let whole = score_run(&inputs, &Settings::default())?;
//! let part = dir.path().join("part.json");
//! std::fs::write(&part, report::json::json(&whole)?)?;
//! // One part merged alone is the run itself.
//! let merged = merge::merge(&[part], DuplicatePolicy::Error, true)?;
//! assert_eq!(merged.summary, whole.summary);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod checks;

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use serde_json::Value;

use crate::aggregate::groups::GroupBy;
use crate::input::duplicates::{
    newest_of, parse_stamp, Dropped, DuplicatePolicy, Kept, Newest, Source,
};
use crate::input::warning::Warning;
use crate::model::report::{assemble_rows, Report, RunFacts, SubsetReport};
use crate::pipeline::outcome::RouteState;
use crate::provenance::{sha256_hex, FileDigest, Provenance};
use crate::route::row::RouteReport;
use crate::settings::Settings;

use crate::input::read::{read_input, FileKind};
use checks::{check_inputs, check_route_set, check_rows, named, scoring_inputs};

pub use crate::model::parts::PartInputs;

/// Why parts cannot be merged. Every message names the part(s) and the field or setting.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum MergeError {
    /// A part cannot be read.
    #[error("{}: cannot read: {source}", file.display())]
    Read {
        /// The part.
        file: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// A part is not an `sds` report (not JSON, another schema, or a field that is not what a
    /// report writes).
    #[error("{}: not an sds report ({why}); a part is the JSON report of a scored run", file.display())]
    NotAReport {
        /// The part.
        file: PathBuf,
        /// What is wrong.
        why: String,
    },
    /// No part given.
    #[error("a merge needs at least one part (the JSON report of a scored run)")]
    NoParts,
    /// Two parts were scored with different settings.
    #[error(
        "{} and {} were scored with different settings: {setting} is {a} in the first and {b} in \
         the second; score every part with the same settings",
        first.display(), second.display()
    )]
    Settings {
        /// The first part.
        first: PathBuf,
        /// The part that differs.
        second: PathBuf,
        /// The first setting that differs (`bounds.yaw_rate`, `protocols`).
        setting: String,
        /// Its value in the first part.
        a: String,
        /// Its value in the second.
        b: String,
    },
    /// Two parts ran different route sets.
    #[error(
        "{} and {} ran different route sets: {a} in the first, {b} in the second; score every \
         part with the same route XML (routes) (and without route_subset = found, which keeps only a \
         part's own routes)",
        first.display(), second.display()
    )]
    RouteSets {
        /// The first part.
        first: PathBuf,
        /// The part that differs.
        second: PathBuf,
        /// The first part's route set.
        a: String,
        /// The second's.
        b: String,
    },
    /// One part scored vehicle logs and another Leaderboard records: `sds score` never mixes
    /// them (`--mcap` or `--results`), so neither does a merge.
    #[error(
        "{} scored vehicle logs (--mcap) and {} scored results (--results): a merge takes parts \
         of one kind, as sds score does; merge each kind apart",
        logs.display(), results.display()
    )]
    MixedKinds {
        /// A part of vehicle logs.
        logs: PathBuf,
        /// A part of results.
        results: PathBuf,
    },
    /// One route has a record in two parts under `--duplicates error`.
    #[error(
        "{route} has a record in {} and in {} ({copies} duplicated route id(s) in all); choose \
         with duplicates = first|last|all",
        first.display(), second.display()
    )]
    Duplicate {
        /// The first duplicated route id.
        route: String,
        /// The part of its first record.
        first: PathBuf,
        /// The part of its second record.
        second: PathBuf,
        /// Duplicated route ids.
        copies: usize,
    },
    /// A policy the merge cannot apply.
    #[error("duplicates = {0}: not available in a merge")]
    Policy(&'static str),
    /// Two parts were scored with other contents of an input that changes a route's figures
    /// (the route XML's bytes, a town's map, the label files).
    #[error("{0}")]
    Inputs(Box<InputsRefusal>),
    /// A part's row is not what `sds score` writes: out of range, its own arithmetic broken,
    /// or the rows not the part's route set (a hand-edited or damaged part).
    #[error(
        "{}: {what}: the part was edited or damaged (sds merge and sds compare take a part's \
         rows as sds score wrote them); score that shard again",
        file.display()
    )]
    Row {
        /// The part.
        file: PathBuf,
        /// The row (`routes[3] (RouteScenario_1_rep0)`), the field and what is wrong.
        what: String,
    },
    /// `--routes` given to a merge is not the route XML the parts were scored with.
    #[error(
        "{}: sha256 {sha}, but the parts were scored with {parts}; give the route XML the parts \
         were scored with",
        file.display()
    )]
    RouteXml {
        /// The file given.
        file: PathBuf,
        /// Its sha256.
        sha: String,
        /// The parts' route XML (files and sha256), or that they had none.
        parts: String,
    },
    /// N smaller than the routes counted.
    #[error("expected_routes = {n} but the parts hold {counted} counted routes")]
    TooFewRoutes {
        /// N.
        n: usize,
        /// Routes counted.
        counted: usize,
    },
    /// Parts grouped by a label map, which the reports do not hold.
    #[error("{}: grouped by {by}, whose label map the report does not hold: merge parts scored without group_by = {by} (or group_by = scenario|town)", file.display())]
    Groups {
        /// The part.
        file: PathBuf,
        /// The grouping.
        by: String,
    },
}

/// Two parts scored with other contents of an input that changes a route's figures
/// ([`MergeError::Inputs`]).
#[derive(Debug, thiserror::Error)]
#[error(
    "{} and {} were scored with different {input}: {a} in the first, {b} in the second; \
     score every part with the same {input} (each part's inputs.provenance lists the files \
     it read and their sha256)",
    first.display(), second.display()
)]
pub struct InputsRefusal {
    /// The first part.
    pub first: PathBuf,
    /// The part that differs.
    pub second: PathBuf,
    /// `route XML`, `map of Town12`, `label files`.
    pub input: String,
    /// The first part's file and sha256 (or that it had none).
    pub a: String,
    /// The second's.
    pub b: String,
}

/// One part, read.
#[derive(Debug)]
pub struct Part {
    /// The file.
    pub file: PathBuf,
    /// What `inputs.parts` says of it.
    pub inputs: PartInputs,
    /// The part's size in bytes.
    pub size: u64,
    /// Its `config`, as written.
    pub config: Value,
    /// The settings that `config` states.
    pub settings: Settings,
    /// Scored with a route XML.
    pub with_xml: bool,
    /// `inputs.route_set`: `(routes, sha256)`.
    pub route_set: (u64, String),
    /// `route_subset`, when `found`.
    pub subset: Option<SubsetReport>,
    /// The rows, in the report's order.
    pub rows: Vec<RouteReport>,
    /// `dropped`.
    pub dropped: Vec<Dropped>,
    /// `warnings`.
    pub warnings: Vec<String>,
    /// `groups.by`, when grouped.
    pub group_by: Option<String>,
    /// The inputs that change a route's figures (route XML, maps, label files), from the
    /// part's provenance (a merged part: its parts').
    pub digests: Vec<FileDigest>,
    /// `inputs.files`: the results files the part read (a merged part: its parts').
    pub files: Vec<crate::input::stored::InputReport>,
}

/// Reads one part: the report read back by the types that wrote it ([`Report::from_json`]),
/// then checked as `sds score` writes a part (each row's own arithmetic, the rows against the
/// part's route set).
///
/// # Errors
/// [`MergeError::Read`], [`MergeError::NotAReport`] (naming the field's JSON path),
/// [`MergeError::Row`].
pub fn read_part(file: &Path) -> Result<Part, MergeError> {
    // Regular files only, opened without blocking, bounded (a FIFO or /dev/zero as a part).
    let bytes = read_input(file, FileKind::Report).map_err(|source| MergeError::Read {
        file: file.to_path_buf(),
        source,
    })?;
    let not = |why: String| MergeError::NotAReport {
        file: file.to_path_buf(),
        why,
    };
    let report = Report::from_json(&bytes).map_err(|e| not(e.to_string()))?;
    let value = |v: Result<Value, serde_json::Error>| v.map_err(|e| not(e.to_string()));
    let config = value(serde_json::to_value(&report.config))?;
    let inputs = value(serde_json::to_value(&report.inputs))?;
    let provenance = &report.inputs.provenance;
    let routes_file = |files: &[FileDigest]| files.iter().any(|f| f.role == "routes");
    // A merged part was scored with a route XML when its parts were.
    let with_xml = routes_file(&provenance.files)
        || report.routes.iter().any(|r| r.state == RouteState::Missing)
        || report.inputs.parts.iter().flatten().any(|p| {
            p.inputs
                .pointer("/provenance/files")
                .and_then(|f| serde_json::from_value::<Vec<FileDigest>>(f.clone()).ok())
                .is_some_and(|f| routes_file(&f))
        });
    let route_set = (
        report.inputs.route_set.routes as u64,
        report.inputs.route_set.sha256.clone(),
    );
    let settings = report.config.clone();
    let wrong = |what: String| MergeError::Row {
        file: file.to_path_buf(),
        what,
    };
    check_rows(&report.routes, &settings).map_err(wrong)?;
    check_route_set(&report.routes, &route_set).map_err(wrong)?;
    let mut digests = Vec::new();
    scoring_inputs(&inputs, &mut digests);
    // A report written before provenance (v1.4) reads with an empty one: no version.
    let sds_version = Some(provenance.sds_version.clone()).filter(|v| !v.is_empty());
    Ok(Part {
        file: file.to_path_buf(),
        inputs: PartInputs {
            file: file.to_path_buf(),
            sha256: sha256_hex(&bytes),
            sds_version,
            inputs,
        },
        size: bytes.len() as u64,
        config,
        settings,
        with_xml,
        route_set,
        subset: report.route_subset,
        warnings: report.warnings.iter().map(ToString::to_string).collect(),
        group_by: report.groups.map(|g| g.by.to_string()),
        files: report.inputs.files,
        dropped: report.dropped,
        rows: report.routes,
        digests,
    })
}

/// The first key (in the report's order) whose value differs, with both values (also
/// [`crate::app::run::scored_by`]'s).
pub(crate) fn first_difference(
    a: &Value,
    b: &Value,
    prefix: &str,
) -> Option<(String, String, String)> {
    let name = |k: &str| {
        if prefix.is_empty() {
            k.to_string()
        } else {
            format!("{prefix}.{k}")
        }
    };
    match (a, b) {
        (Value::Object(x), Value::Object(y)) => {
            let mut keys: Vec<&String> = x.keys().chain(y.keys()).collect();
            keys.sort();
            keys.dedup();
            keys.into_iter().find_map(|k| match (x.get(k), y.get(k)) {
                (Some(p), Some(q)) => first_difference(p, q, &name(k)),
                (p, q) => Some((
                    name(k),
                    p.map_or_else(|| "absent".into(), Value::to_string),
                    q.map_or_else(|| "absent".into(), Value::to_string),
                )),
            })
        }
        _ if a == b => None,
        _ => Some((prefix.to_string(), a.to_string(), b.to_string())),
    }
}

/// A part of vehicle logs: its warnings say so (a merged part's, prefixed by its part), as
/// every `sds score --mcap` report does (docs/SCORE.md section 2.4).
fn vehicle_logs(part: &Part) -> bool {
    part.warnings
        .iter()
        .any(|w| w.ends_with(crate::model::vehicle_log::NO_LEADERBOARD))
}

/// Merges the reports in `files` (docs/SCORE.md §13.2): reads each ([`read_part`]) and merges them
/// ([`merge_parts`]).
///
/// # Errors
/// As [`read_part`] and [`merge_parts`].
pub fn merge(
    files: &[PathBuf],
    duplicates: DuplicatePolicy,
    host: bool,
) -> Result<Report, MergeError> {
    // Each part is checked against the first as it is read, then slimmed: 2,000 one-route
    // parts held 24 KB each, most of it the settings every part repeats.
    let mut parts: Vec<Part> = Vec::with_capacity(files.len());
    for f in files {
        let mut part = read_part(f)?;
        if let Some(first) = parts.first() {
            check_part(first, &part)?;
            slim(&mut part);
        }
        parts.push(part);
    }
    merge_checked(parts, duplicates, host)
}

/// The report `sds score` would write over the union of the parts' inputs: the parts must
/// agree on `config` and (when scored with a route XML) the route set; a route missing in one
/// part takes another's record; records of one route id in two parts follow `duplicates`
/// (`error`, `first`, `last`, `all`). `inputs` lists the parts, `warnings` keeps each part's
/// warnings, naming the part; `host` names this machine in the provenance.
///
/// # Errors
/// [`MergeError::NoParts`], [`MergeError::Settings`], [`MergeError::RouteSets`],
/// [`MergeError::Duplicate`], [`MergeError::Policy`], [`MergeError::TooFewRoutes`],
/// [`MergeError::Groups`], [`MergeError::MixedKinds`].
pub fn merge_parts(
    parts: Vec<Part>,
    duplicates: DuplicatePolicy,
    host: bool,
) -> Result<Report, MergeError> {
    // Taken by value: the merged rows are the parts' own, moved, not copies.
    let first = parts.first().ok_or(MergeError::NoParts)?;
    for p in &parts[1..] {
        check_part(first, p)?;
    }
    merge_checked(parts, duplicates, host)
}

/// What a part must share with the first: its settings, route set, scoring inputs and kind
/// (vehicle logs or results).
fn check_part(first: &Part, p: &Part) -> Result<(), MergeError> {
    if let Some((setting, a, b)) = first_difference(&first.config, &p.config, "") {
        return Err(MergeError::Settings {
            first: first.file.clone(),
            second: p.file.clone(),
            setting,
            a,
            b,
        });
    }
    let set = |q: &Part| match (q.with_xml, &q.subset) {
        (false, _) => "none (no route XML)".to_string(),
        (true, s) => format!(
            "{} routes, sha256 {}{}",
            q.route_set.0,
            q.route_set.1,
            s.as_ref().map_or_else(String::new, |s| format!(
                " (route_subset = found, of {})",
                s.of
            ))
        ),
    };
    let differ = first.with_xml != p.with_xml
        || (first.with_xml && (first.route_set != p.route_set || first.subset != p.subset));
    if differ {
        return Err(MergeError::RouteSets {
            first: first.file.clone(),
            second: p.file.clone(),
            a: set(first),
            b: set(p),
        });
    }
    check_inputs((&first.digests, &first.rows), (&p.digests, &p.rows)).map_err(|d| {
        MergeError::Inputs(Box::new(InputsRefusal {
            first: first.file.clone(),
            second: p.file.clone(),
            input: d.input,
            a: d.a,
            b: d.b,
        }))
    })?;
    let logs = vehicle_logs(first);
    if vehicle_logs(p) != logs {
        let (l, r) = if logs { (first, p) } else { (p, first) };
        return Err(MergeError::MixedKinds {
            logs: l.file.clone(),
            results: r.file.clone(),
        });
    }
    Ok(())
}

/// A part checked against the first keeps only what the merge reads of it: the first part's
/// `config`, settings and scoring inputs stand for every part's.
fn slim(part: &mut Part) {
    part.config = Value::Null;
    part.settings = Settings::default();
    part.digests = Vec::new();
}

/// The merge of parts checked against the first ([`check_part`]): their rows move into the
/// merged report (copied, they were held twice: a merge of 1,000 parts of 220 routes peaked
/// at twice the rows' size).
fn merge_checked(
    mut parts: Vec<Part>,
    duplicates: DuplicatePolicy,
    host: bool,
) -> Result<Report, MergeError> {
    let first = parts.first().ok_or(MergeError::NoParts)?;
    let logs = vehicle_logs(first);
    let mut settings = first.settings.clone();
    // The first part's missing routes, before its rows move.
    let first_missing: Vec<RouteReport> = first
        .rows
        .iter()
        .filter(|r| r.state == RouteState::Missing)
        .cloned()
        .collect();
    // Records in input order (part by part), then the routes no part has a record of.
    let mut records: Vec<(usize, RouteReport)> = Vec::new();
    for (i, p) in parts.iter_mut().enumerate() {
        records.extend(
            std::mem::take(&mut p.rows)
                .into_iter()
                .filter(|r| r.state != RouteState::Missing)
                .map(|r| (i, r)),
        );
    }
    let first = &parts[0];
    let (records, dropped, applied) = deduplicate(records, &parts, duplicates)?;
    // The merged report states the rule the merge applied to records of one route in several
    // parts; with none, the parts' own rule stands.
    if applied {
        settings.duplicates = duplicates;
    }
    let recorded: std::collections::HashSet<&str> = records
        .iter()
        .filter_map(|r| r.route_id.as_deref())
        .collect();
    let missing: Vec<RouteReport> = first_missing
        .into_iter()
        .filter(|r| {
            r.route_id
                .as_deref()
                .is_none_or(|id| !recorded.contains(id))
        })
        .collect();
    let mut rows = records;
    rows.extend(missing);
    let counted = rows
        .iter()
        .filter(|r| r.state != RouteState::Foreign)
        .filter(|r| !first.with_xml || r.route_id.is_some())
        .count();
    let n = settings.expected_routes.unwrap_or(counted);
    if n < counted {
        return Err(MergeError::TooFewRoutes { n, counted });
    }
    let mut provenance = Provenance::new(&settings, std::iter::empty());
    provenance.host = if host {
        crate::provenance::host_name()
    } else {
        None
    };
    let facts = RunFacts {
        n,
        inputs: parts.iter().flat_map(|p| p.files.iter().cloned()).collect(),
        dropped: parts
            .iter()
            .flat_map(|p| p.dropped.iter().cloned())
            .chain(dropped.iter().cloned())
            .collect(),
        provenance: Provenance {
            files: parts
                .iter()
                .map(|p| FileDigest {
                    file: p.file.clone(),
                    role: "part".into(),
                    size: p.size,
                    sha256: Some(p.inputs.sha256.clone()),
                })
                .collect(),
            ..provenance
        },
        ..RunFacts::default()
    };
    let mut report = assemble_rows(rows, &settings, facts);
    if logs {
        // As `sds score --mcap`: the rows hold no Leaderboard figure, nor does the summary.
        crate::model::vehicle_log::without_leaderboard(&mut report);
    }
    report.route_subset = first.subset.clone();
    report.inputs.parts = Some(parts.iter().map(|p| p.inputs.clone()).collect());
    let mut warnings: Vec<Warning> = parts
        .iter()
        .flat_map(|p| {
            p.warnings.iter().map(|w| Warning::Part {
                part: p.file.clone(),
                text: w.clone(),
            })
        })
        .collect();
    // Same settings, but another tool version may compute them differently: say so.
    let mut versions: Vec<(&str, Vec<String>)> = Vec::new();
    for p in &parts {
        let v = p.inputs.sds_version.as_deref().unwrap_or("unknown");
        let file = p.file.display().to_string();
        match versions.iter_mut().find(|(w, _)| *w == v) {
            Some((_, files)) => files.push(file),
            None => versions.push((v, vec![file])),
        }
    }
    if versions.len() > 1 {
        let list: Vec<String> = versions
            .iter()
            .map(|(v, files)| format!("{v}: {}", crate::input::warning::id_list(files)))
            .collect();
        warnings.push(Warning::Recorded(format!(
            "merge: the parts were scored by different sds versions ({}); one version's figures \
             may differ from another's",
            list.join("; ")
        )));
    }
    if !dropped.is_empty() {
        warnings.push(Warning::Recorded(format!(
            "merge: {} record(s) of route ids recorded in several parts left out under \
             duplicates = {} (see dropped)",
            dropped.len(),
            duplicates.name()
        )));
    }
    report.warnings = warnings;
    report.files_read = parts.iter().map(|p| p.file.clone()).collect();
    if let Some(by) = &first.group_by {
        let g = match GroupBy::from_name(by) {
            Some(g @ (GroupBy::Scenario | GroupBy::Town)) => g,
            _ => {
                return Err(MergeError::Groups {
                    file: first.file.clone(),
                    by: by.clone(),
                })
            }
        };
        let (g, _) =
            crate::aggregate::groups::groups(&report.routes, report.summary.routes, g, None)
                .map_err(|_| MergeError::Groups {
                    file: first.file.clone(),
                    by: by.clone(),
                })?;
        report.groups = Some(g);
    }
    Ok(report)
}

/// `--routes` of a merge (for `--rerun-xml`) is the route XML the parts were scored with.
///
/// # Errors
/// [`MergeError::RouteXml`] with both hashes; [`MergeError::Read`] when it cannot be read.
pub fn check_route_xml(report: &Report, file: &Path) -> Result<(), MergeError> {
    let given = FileDigest::of(file, "routes");
    let Some(sha) = given.sha256 else {
        return Err(MergeError::Read {
            file: file.to_path_buf(),
            source: std::fs::File::open(file)
                .err()
                .unwrap_or_else(|| std::io::Error::other("cannot be read")),
        });
    };
    let mut digests = Vec::new();
    for p in report.inputs.parts.iter().flatten() {
        scoring_inputs(&p.inputs, &mut digests);
    }
    let theirs: Vec<&FileDigest> = digests.iter().filter(|d| d.role == "routes").collect();
    if !theirs.is_empty() && theirs.iter().all(|d| d.sha256.as_deref() == Some(&sha)) {
        return Ok(());
    }
    let mut parts: Vec<String> = theirs.iter().map(|d| named(d)).collect();
    parts.dedup();
    Err(MergeError::RouteXml {
        file: file.to_path_buf(),
        sha,
        parts: if parts.is_empty() {
            "no route XML".into()
        } else {
            parts.join(", ")
        },
    })
}

/// Records of one route id in several parts, under `policy`: the records kept (in input
/// order), the copies dropped, and whether the policy decided any (a route id in two parts).
fn deduplicate(
    records: Vec<(usize, RouteReport)>,
    parts: &[Part],
    policy: DuplicatePolicy,
) -> Result<(Vec<RouteReport>, Vec<Dropped>, bool), MergeError> {
    // Per route id, the indices of its records in parts other than the first one holding it.
    let mut by_id: HashMap<&str, Vec<usize>> = HashMap::new();
    for (i, (_, r)) in records.iter().enumerate() {
        if let Some(id) = r.route_id.as_deref() {
            by_id.entry(id).or_default().push(i);
        }
    }
    // Copies inside one part were the part's own choice (scored under `all`): only copies in
    // different parts are duplicates of the merge.
    let mut dup: Vec<(&str, Vec<usize>)> = by_id
        .into_iter()
        .filter(|(_, ix)| ix.iter().any(|&i| records[i].0 != records[ix[0]].0))
        .collect();
    dup.sort_by_key(|(_, ix)| ix[0]);
    if dup.is_empty() || policy == DuplicatePolicy::All {
        let applied = !dup.is_empty();
        return Ok((
            records.into_iter().map(|(_, r)| r).collect(),
            Vec::new(),
            applied,
        ));
    }
    if policy == DuplicatePolicy::Error {
        let (id, ix) = &dup[0];
        let second = ix
            .iter()
            .find(|&&i| records[i].0 != records[ix[0]].0)
            .copied()
            .unwrap_or(ix[0]);
        return Err(MergeError::Duplicate {
            route: id.to_string(),
            first: parts[records[ix[0]].0].file.clone(),
            second: parts[records[second].0].file.clone(),
            copies: dup.len(),
        });
    }
    let mut drop = vec![false; records.len()];
    let mut kept_of: Vec<Option<Kept>> = vec![None; records.len()];
    let mut dropped = Vec::new();
    for (id, ix) in &dup {
        let n = ix.len();
        let stamp = |i: usize| records[i].1.stamp.clone();
        let (keep, why) = match policy {
            DuplicatePolicy::First => (ix[0], format!("first of {n} copies in input order")),
            DuplicatePolicy::Newest => {
                let stamps: Vec<Option<[u32; 5]>> = ix
                    .iter()
                    .map(|&i| stamp(i).as_deref().and_then(parse_stamp))
                    .collect();
                match newest_of(&stamps) {
                    Newest::Chosen { pos, why, .. } => (ix[pos], why),
                    // The results files are on the nodes that scored the parts: their
                    // modification times are not here to decide.
                    Newest::CouldWrap(texts) => (
                        ix[n - 1],
                        format!(
                            "save_name time stamps {} lie more than half a year apart and carry \
                             no year, so they could wrap one: kept the last of {n} copies in \
                             input order (the parts' files are not here to compare)",
                            texts.join(", ")
                        ),
                    ),
                }
            }
            _ => (ix[n - 1], format!("last of {n} copies in input order")),
        };
        let source = |i: usize| {
            records[i].1.source.clone().unwrap_or(Source {
                file: PathBuf::new(),
                index: 0,
            })
        };
        for &i in ix.iter().filter(|&&i| i != keep) {
            drop[i] = true;
            dropped.push(Dropped {
                route_id: id.to_string(),
                source: source(i),
                kept: source(keep),
            });
        }
        kept_of[keep] = Some(Kept {
            policy: policy.name(),
            copies: n,
            stamp: stamp(keep),
            why,
            source: source(keep),
            by_order: false,
            year_wrap: false,
        });
    }
    let kept = records
        .into_iter()
        .zip(drop)
        .zip(kept_of)
        .filter(|((_, d), _)| !d)
        .map(|(((_, mut r), _), k)| {
            if k.is_some() {
                r.kept = k;
            }
            r
        })
        .collect();
    Ok((kept, dropped, true))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_difference_is_named_with_both_values() {
        let a = serde_json::json!({"a": 1, "b": {"x": 1, "y": [1]}, "c": 3});
        let b = serde_json::json!({"a": 1, "b": {"x": 1, "y": [2]}, "c": 4});
        assert_eq!(
            first_difference(&a, &b, ""),
            Some(("b.y".into(), "[1]".into(), "[2]".into()))
        );
        assert_eq!(first_difference(&a, &a, ""), None);
        let c = serde_json::json!({"a": 1});
        assert_eq!(
            first_difference(&c, &a, ""),
            Some(("b".into(), "absent".into(), a["b"].to_string()))
        );
    }
}
