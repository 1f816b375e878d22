//! What a merge checks of its parts beyond their schema (`docs/SCORE.md`, "Merging"): each
//! row's ranges and own arithmetic, the rows against the part's own route set (a part is taken
//! as `sds score` wrote it, never on trust), and the inputs that change a route's figures
//! (route XML, each town's map, label files) alike in every part.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use serde_json::Value;

use crate::input::route_set::route_set_id;
use crate::pipeline::outcome::RouteState;
use crate::provenance::FileDigest;
use crate::route::row::{counted_routes, RouteReport};
use crate::settings::Settings;

/// The largest difference between a row's `score_composed` and `score_route × score_penalty`
/// allowed: the evaluator writes both the product and the penalty rounded to 6 decimals, so
/// the product of the written figures may be off by up to `score_route × 5e-7` beside the
/// product's own rounding (SimLingo's route 23687: 100 × 0.986199 against 98.61995).
fn composed_tolerance(score_route: f64) -> f64 {
    1e-6 + 5e-7 * score_route.abs() + 1e-9
}

/// Each row's figures in their ranges and its own arithmetic: `score_composed` is
/// `score_route × score_penalty` (to the evaluator's 6 decimals), DS_safe is what the
/// settings' factors give from the row's counts, comfort is its comfortable share of chunks.
///
/// # Errors
/// The first row that is not what `sds score` writes: its path, id, field and value.
pub(crate) fn check_rows(rows: &[RouteReport], settings: &Settings) -> Result<(), String> {
    for (i, r) in rows.iter().enumerate() {
        let name = format!(
            "routes[{i}] ({})",
            r.route_id.as_deref().unwrap_or("no route_id")
        );
        check_row(r, settings).map_err(|e| format!("{name}: {e}"))?;
    }
    Ok(())
}

/// A number as an error shows it: `1e308`, never 309 digits.
fn num(x: f64) -> String {
    if x != 0.0 && !(1e-4..1e9).contains(&x.abs()) {
        format!("{x:e}")
    } else {
        x.to_string()
    }
}

/// A figure in `lo..=hi` (`hi` none: not negative).
fn range(name: &str, x: Option<f64>, lo: f64, hi: Option<f64>) -> Result<(), String> {
    match (x, hi) {
        (Some(v), Some(hi)) if !(lo..=hi).contains(&v) => {
            Err(format!("{name} {} is outside {lo}..{hi}", num(v)))
        }
        (Some(v), None) if v < lo => Err(format!("{name} {} is negative", num(v))),
        _ => Ok(()),
    }
}

/// Two figures equal within `tol` relative to the larger (and `tol` absolute near 0).
fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * a.abs().max(b.abs()).max(1.0)
}

fn check_row(r: &RouteReport, settings: &Settings) -> Result<(), String> {
    range("score_route", r.score_route, 0.0, Some(100.0))?;
    range("score_penalty", r.score_penalty, 0.0, Some(1.0))?;
    range("score_composed", r.score_composed, 0.0, Some(100.0))?;
    range("ds_safe", r.ds_safe, 0.0, Some(100.0))?;
    range("p_safe", r.p_safe, 0.0, Some(1.0))?;
    range("comfort.score", r.comfort.score, 0.0, Some(1.0))?;
    range(
        "comfort.moving_score",
        r.comfort.moving_score,
        0.0,
        Some(1.0),
    )?;
    range("smoothness", r.smoothness, 0.0, Some(1.0))?;
    range("stationary_share", r.stationary_share, 0.0, Some(1.0))?;
    range("distance_m", r.distance_m, 0.0, None)?;
    range("driven_km", r.driven_km, 0.0, None)?;
    range("efficiency", r.efficiency, 0.0, None)?;
    if let (Some(c), Some(route), Some(p)) = (r.score_composed, r.score_route, r.score_penalty) {
        if (c - route * p).abs() > composed_tolerance(route) {
            return Err(format!(
                "score_composed {} is not score_route × score_penalty ({} × {} = {})",
                num(c),
                num(route),
                num(p),
                num(route * p)
            ));
        }
    }
    let m = &r.comfort;
    if m.comfortable > m.chunks || m.moving_comfortable > m.moving_chunks {
        return Err(format!(
            "comfort: {} comfortable of {} chunks ({} of {} moving)",
            m.comfortable, m.chunks, m.moving_comfortable, m.moving_chunks
        ));
    }
    for (what, score, good, all) in [
        ("comfort.score", m.score, m.comfortable, m.chunks),
        (
            "comfort.moving_score",
            m.moving_score,
            m.moving_comfortable,
            m.moving_chunks,
        ),
    ] {
        if let Some(s) = score.filter(|_| all > 0) {
            let share = f64::from(good) / f64::from(all);
            if !close(s, share, 1e-9) {
                return Err(format!(
                    "{what} {} is not {good} comfortable of {all} chunks",
                    num(s)
                ));
            }
        }
    }
    let l = &r.lateral;
    if l.scored_chunks > l.chunks || l.anomalous.saturating_add(l.critical) > l.scored_chunks {
        return Err(format!(
            "lateral: {} anomalous and {} critical of {} scored chunks ({} chunks)",
            l.anomalous, l.critical, l.scored_chunks, l.chunks
        ));
    }
    // DS_safe from the row's own counts, with the part's factors (its `config`).
    if let (RouteState::Scored, Some(ds), Some(route), Some(p)) =
        (&r.state, r.ds_safe, r.score_route, r.score_penalty)
    {
        let mut summary = monitor_core::RouteSummary::ZERO;
        summary.collisions.nodecel = r.collisions.nodecel;
        summary.lateral.anomalous = l.anomalous;
        summary.lateral.critical = l.critical;
        let record = monitor_core::score::RecordScores {
            score_route: route,
            score_penalty: p,
            workzone: r.collisions.workzone,
        };
        let safe = monitor_core::score::ds_safe(&summary, &record, &settings.core.factors);
        if !close(ds, safe.ds_safe, 1e-9) {
            return Err(format!(
                "ds_safe {} is not what its scores and counts give ({})",
                num(ds),
                num(safe.ds_safe)
            ));
        }
        if let Some(ps) = r.p_safe.filter(|x| !close(*x, safe.p_safe, 1e-9)) {
            return Err(format!(
                "p_safe {} is not what its penalty and work-zone contacts give ({})",
                num(ps),
                num(safe.p_safe)
            ));
        }
    }
    Ok(())
}

/// The part's counted rows are its route set: their ids give its `inputs.route_set` (a row
/// added, dropped or renamed, or a foreign row made counted, changes it).
///
/// # Errors
/// Both fingerprints.
pub(crate) fn check_route_set(rows: &[RouteReport], stated: &(u64, String)) -> Result<(), String> {
    let got = route_set_id(counted_routes(rows).filter_map(|r| r.route_id.as_deref()));
    if got.routes as u64 == stated.0 && got.sha256 == stated.1 {
        return Ok(());
    }
    Err(format!(
        "its counted rows ({} routes, sha256 {}) are not its inputs.route_set ({} routes, \
         sha256 {}): a row was added, removed or renamed, or a foreign or missing route made \
         counted",
        got.routes, got.sha256, stated.0, stated.1
    ))
}

/// The files of `inputs` (a report's) that change a route's figures: the route XML, maps and
/// label files of its provenance, or for a merged report those of its parts, recursively.
pub(crate) fn scoring_inputs(inputs: &Value, out: &mut Vec<FileDigest>) {
    if let Some(parts) = inputs.get("parts").and_then(Value::as_array) {
        for p in parts {
            if let Some(i) = p.get("inputs") {
                scoring_inputs(i, out);
            }
        }
        return;
    }
    let files = inputs
        .pointer("/provenance/files")
        .and_then(Value::as_array)
        .map_or(&[][..], Vec::as_slice);
    for f in files {
        if let Ok(d) = serde_json::from_value::<FileDigest>(f.clone()) {
            if matches!(d.role.as_str(), "routes" | "map" | "labels") {
                out.push(d);
            }
        }
    }
}

/// The town of a map file: its name without `.xodr` (and without CARLA's `_Opt`), as the maps
/// folder is searched (`Town12.xodr`, `Town12_Opt.xodr`, `Town12/OpenDrive/Town12.xodr`).
fn map_town(file: &Path) -> Option<String> {
    let stem = file.file_stem()?.to_str()?;
    Some(stem.strip_suffix("_Opt").unwrap_or(stem).to_string())
}

/// A digest as an error names it.
pub(crate) fn named(d: &FileDigest) -> String {
    format!(
        "sha256 {} ({})",
        d.sha256
            .as_deref()
            .unwrap_or("unknown: the file could not be read again"),
        d.file.display()
    )
}

/// The towns whose routes have a record (the towns whose maps a part loaded).
fn towns(rows: &[RouteReport]) -> BTreeSet<&str> {
    rows.iter()
        .filter(|r| matches!(r.state, RouteState::Scored | RouteState::Invalid(_)))
        .filter_map(|r| r.town.as_deref())
        .collect()
}

/// An input two parts were scored with in other contents: what it is, and each part's files
/// and sha256 (or that it had none).
pub(crate) struct InputsDiffer {
    /// `route XML`, `map of Town12`, `label files`.
    pub input: String,
    /// The first part's.
    pub a: String,
    /// The second's.
    pub b: String,
}

/// Two parts (each its scoring inputs, [`scoring_inputs`], and its rows) scored with the same
/// route XML bytes, the same map of each town both parts' routes use (a part with a map and
/// one without disagree), and the same label files.
///
/// # Errors
/// The first input that differs.
pub(crate) fn check_inputs(
    a: (&[FileDigest], &[RouteReport]),
    b: (&[FileDigest], &[RouteReport]),
) -> Result<(), InputsDiffer> {
    let differ = |input: String, a: String, b: String| InputsDiffer { input, a, b };
    let of_role = |d: &[FileDigest], role: &str| -> BTreeMap<Option<String>, FileDigest> {
        d.iter()
            .filter(|d| d.role == role)
            .map(|d| (d.sha256.clone(), d.clone()))
            .collect()
    };
    let list = |m: &BTreeMap<Option<String>, FileDigest>, none: &str| {
        if m.is_empty() {
            none.to_string()
        } else {
            m.values().map(named).collect::<Vec<_>>().join(", ")
        }
    };
    for (role, input, none) in [
        ("routes", "route XML", "no route XML"),
        ("labels", "label files", "no label file"),
    ] {
        let (x, y) = (of_role(a.0, role), of_role(b.0, role));
        if x.keys().ne(y.keys()) {
            return Err(differ(input.into(), list(&x, none), list(&y, none)));
        }
    }
    let maps = |d: &[FileDigest]| -> BTreeMap<String, FileDigest> {
        d.iter()
            .filter(|d| d.role == "map")
            .filter_map(|d| map_town(&d.file).map(|t| (t, d.clone())))
            .collect()
    };
    let (ma, mb) = (maps(a.0), maps(b.0));
    for town in towns(a.1).intersection(&towns(b.1)) {
        let (x, y) = (ma.get(*town), mb.get(*town));
        if x.map(|d| &d.sha256) != y.map(|d| &d.sha256) {
            let show = |d: Option<&FileDigest>| {
                d.map_or_else(|| "no map (scored without one)".to_string(), named)
            };
            return Err(differ(format!("map of {town}"), show(x), show(y)));
        }
    }
    Ok(())
}
