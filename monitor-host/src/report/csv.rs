//! The CSV rendering: one line per route (the `csv` crate quotes what needs quoting: `"`, `,`,
//! CR, LF). Numbers are printed as the JSON report prints them (`100.0`, `0.39`); `source` is
//! `file#index`. String cells from the inputs are neutralised against formula injection
//! ([`crate::report::escape::csv_cell`]); numbers are written as numbers.

use crate::model::report::Report;
use crate::report::escape::csv_cell;
use crate::report::protocol_csv;
use crate::route::row::RouteReport;

/// The header line's columns.
pub const COLUMNS: [&str; 35] = [
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
    "moving_chunks",
    "moving_comfortable",
    "moving_comfort",
    "distance_m",
    "stationary_share",
    "p_safe",
    "ds_safe",
    "reason",
];

/// A float as JSON prints it (`100.0`, `0.05`), as the shortest decimal of its 15 significant
/// digits (a product such as 50.15 × 0.6 prints 30.09, not 30.089999999999996); empty when
/// absent.
///
/// ```
/// use monitor_host::report::csv::float;
/// assert_eq!(float(Some(50.15 * 0.6)), "30.09");
/// assert_eq!((float(Some(100.0)), float(Some(0.05)), float(None)), ("100.0".into(), "0.05".into(), "".into()));
/// assert_eq!(float(Some(1.0 / 3.0)), "0.333333333333333");
/// ```
pub fn float(x: Option<f64>) -> String {
    x.map(|v| {
        let v = if v.is_finite() {
            format!("{v:.14e}").parse().unwrap_or(v)
        } else {
            v
        };
        serde_json::to_string(&v).unwrap_or_default()
    })
    .unwrap_or_default()
}

fn num(x: Option<f64>) -> String {
    float(x)
}

fn row(r: &RouteReport) -> [String; 35] {
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
        r.comfort.moving_chunks.to_string(),
        r.comfort.moving_comfortable.to_string(),
        o(r.comfort.moving_score),
        o(r.distance_m),
        o(r.stationary_share),
        o(r.p_safe),
        o(r.ds_safe),
        s(&r.reason),
    ]
}

/// One CSV line per route, after a header line ([`COLUMNS`], then the asked protocols'
/// columns, [`protocol_csv::route_columns`]); empty cells for absent values.
pub fn csv(report: &Report) -> Vec<u8> {
    let mut w = ::csv::Writer::from_writer(Vec::new());
    // Writing to memory cannot fail; an error here would be a bug in the csv crate.
    let asked = &report.config.protocols;
    let mut header: Vec<String> = COLUMNS.iter().map(|c| c.to_string()).collect();
    header.extend(protocol_csv::route_columns(asked));
    let _ = w.write_record(&header);
    for r in &report.routes {
        let mut cells = row(r).to_vec();
        cells.extend(protocol_csv::route_cells(r.protocols.as_ref(), asked));
        let _ = w.write_record(cells);
    }
    w.into_inner().unwrap_or_default()
}

/// The columns of [`groups_csv`].
pub const GROUP_COLUMNS: [&str; 16] = [
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
    "mean_comfort_moving",
    "mean_stationary_share",
    "distance_km",
];

/// The report's `groups` as CSV: one line per group, then `combined`; after [`GROUP_COLUMNS`],
/// one column per ability rate and one `routes_with_<list>` column per infraction list. `None`
/// when the report has no groups.
pub fn groups_csv(report: &Report) -> Option<Vec<u8>> {
    use crate::aggregate::aggregates::Aggregates;
    use crate::route::ability::ABILITIES;
    let g = report.groups.as_ref()?;
    let o = float;
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
    let asked = &report.config.protocols;
    header.extend(protocol_csv::group_columns(asked));
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
            o(a.scores.motion.mean_comfort_moving),
            o(a.scores.motion.mean_stationary_share),
            o(a.scores.motion.distance_km),
        ];
        row.extend(ab.rates().into_iter().map(o));
        row.extend(lists.iter().map(|l| a.infraction_routes.get(l).to_string()));
        row.extend(protocol_csv::group_cells(a.protocols.as_ref(), asked));
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
