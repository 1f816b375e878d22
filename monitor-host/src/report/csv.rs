//! The CSV rendering: one line per route (the `csv` crate quotes what needs quoting: `"`, `,`,
//! CR, LF). Numbers are printed as the JSON report prints them (`100.0`, `0.39`); `source` is
//! `file#index`. String cells from the inputs are neutralised against formula injection
//! ([`crate::report::escape::csv_cell`]); numbers are written as numbers.

use crate::report::escape::csv_cell;
use crate::report::model::{Report, RouteReport};

/// The header line's columns.
pub const COLUMNS: [&str; 30] = [
    "route_id",
    "scenario_type",
    "town",
    "weather_id",
    "status",
    "state",
    "success",
    "source",
    "dt",
    "score_route",
    "score_penalty",
    "score_composed",
    "frames",
    "gaps",
    "pedestrian",
    "vehicle",
    "layout",
    "workzone",
    "unaligned",
    "exempt",
    "nodecel",
    "lateral_chunks",
    "anomalous",
    "critical",
    "comfort_chunks",
    "comfortable",
    "comfort",
    "p_safe",
    "ds_safe",
    "reason",
];

/// A float as JSON prints it (`100.0`, `0.05`); empty when absent.
fn num(x: Option<f64>) -> String {
    x.and_then(|v| serde_json::to_string(&v).ok())
        .unwrap_or_default()
}

fn row(r: &RouteReport) -> [String; 30] {
    let s = |x: &Option<String>| csv_cell(x.as_deref().unwrap_or_default()).into_owned();
    let o = num;
    let c = &r.collisions;
    [
        s(&r.route_id),
        s(&r.scenario_type),
        s(&r.town),
        s(&r.weather_id),
        s(&r.status),
        r.state.name().to_string(),
        r.success.to_string(),
        r.source.as_ref().map_or_else(String::new, |x| {
            csv_cell(&format!("{}#{}", x.file.display(), x.index)).into_owned()
        }),
        o(r.dt),
        o(r.score_route),
        o(r.score_penalty),
        o(r.score_composed),
        r.frames.to_string(),
        r.gaps.to_string(),
        c.pedestrian.to_string(),
        c.vehicle.to_string(),
        c.layout.to_string(),
        c.workzone.to_string(),
        c.unaligned.to_string(),
        c.exempt.to_string(),
        c.nodecel.to_string(),
        r.lateral.chunks.to_string(),
        r.lateral.anomalous.to_string(),
        r.lateral.critical.to_string(),
        r.comfort.chunks.to_string(),
        r.comfort.comfortable.to_string(),
        o(r.comfort.score),
        o(r.p_safe),
        o(r.ds_safe),
        s(&r.reason),
    ]
}

/// One CSV line per route, after a header line ([`COLUMNS`]); empty cells for absent values.
pub fn csv(report: &Report) -> Vec<u8> {
    let mut w = ::csv::Writer::from_writer(Vec::new());
    // Writing to memory cannot fail; an error here would be a bug in the csv crate.
    let _ = w.write_record(COLUMNS);
    for r in &report.routes {
        let _ = w.write_record(row(r));
    }
    w.into_inner().unwrap_or_default()
}

/// The columns of [`groups_csv`].
pub const GROUP_COLUMNS: [&str; 13] = [
    "by",
    "label",
    "routes",
    "driving_score",
    "success_rate",
    "mean_ds_safe",
    "mean_comfort",
    "sds",
    "collision_rate",
    "efficiency",
    "smoothness",
    "ability_mean",
    "comfort_routes",
];

/// The report's `groups` as CSV: one line per group, then `combined`; after [`GROUP_COLUMNS`],
/// one column per ability rate and one `routes_with_<list>` column per infraction list. `None`
/// when the report has no groups.
pub fn groups_csv(report: &Report) -> Option<Vec<u8>> {
    use crate::aggregate::ability::ABILITIES;
    use crate::aggregate::aggregates::Aggregates;
    let g = report.groups.as_ref()?;
    let o = |x: Option<f64>| x.map_or_else(String::new, |v| v.to_string());
    let lists: Vec<String> = g
        .combined
        .infraction_routes
        .0
        .iter()
        .map(|(n, _)| n.clone())
        .collect();
    let mut header: Vec<String> = GROUP_COLUMNS.iter().map(|c| c.to_string()).collect();
    header.extend(ABILITIES.iter().map(|(n, _)| n.to_string()));
    header.extend(
        lists
            .iter()
            .map(|l| csv_cell(&format!("routes_with_{l}")).into_owned()),
    );
    let line = |label: &str, a: &Aggregates| {
        let ab = a.ability.clone().unwrap_or_default();
        let mut row = vec![
            csv_cell(g.by).into_owned(),
            // Labels come from the inputs (scenario names, towns, label files).
            csv_cell(label).into_owned(),
            a.routes.to_string(),
            o(a.scores.driving_score),
            o(a.scores.success_rate),
            o(a.scores.mean_ds_safe),
            o(a.scores.mean_comfort),
            o(a.scores.sds),
            o(a.scores.collision_rate),
            o(a.efficiency),
            o(a.smoothness),
            o(ab.mean),
            a.scores.comfort_routes.to_string(),
        ];
        row.extend(ab.rates().into_iter().map(o));
        row.extend(lists.iter().map(|l| a.infraction_routes.get(l).to_string()));
        row
    };
    let mut w = ::csv::Writer::from_writer(Vec::new());
    let _ = w.write_record(&header);
    for r in &g.rows {
        let _ = w.write_record(line(&r.label, &r.aggregates));
    }
    let _ = w.write_record(line("combined", &g.combined));
    Some(w.into_inner().unwrap_or_default())
}
