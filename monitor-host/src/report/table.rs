//! The tables the papers print, as [`Grid`]s rendered in text, Markdown or LaTeX: Bench2Drive's
//! main table (DS, SR, efficiency, comfortness, the five abilities and their mean), the
//! Safe2Drive Table 1 row, a Table 2-style breakdown per group with the combined row, and with
//! a weather breakdown a Table 3-style infraction table. `docs/TABLES.md` explains every column.

use crate::aggregate::aggregates::Aggregates;
use crate::aggregate::groups::{GroupBy, Groups};
use crate::model::report::Report;
use crate::report::grid::{Grid, Style};

/// The infraction lists of the Table 3-style breakdown, with their headings (the paper's four).
pub const TABLE3_LISTS: [(&str, &str); 4] = [
    ("red_light", "Red light"),
    ("collisions_layout", "Layout coll."),
    ("outside_route_lanes", "Outside lanes"),
    ("vehicle_blocked", "Blocked"),
];

/// Options of the tables.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct TableOptions {
    /// Infraction lists shown in the Table 3-style breakdown after [`TABLE3_LISTS`].
    pub extra_infractions: Vec<String>,
}

fn num(x: Option<f64>, digits: usize) -> String {
    x.map_or_else(|| "-".to_string(), |v| format!("{v:.digits$}"))
}

fn pct(x: Option<f64>) -> String {
    num(x.map(|v| 100.0 * v), 2)
}

/// The columns of Bench2Drive's main table (also one row per model in `sds compare`).
pub(crate) const BENCH2DRIVE_COLUMNS: [&str; 10] = [
    "DS",
    "SR(%)",
    "Efficiency",
    "Comfortness",
    "Merging",
    "Overtaking",
    "Emergency Brake",
    "Give Way",
    "Traffic Sign",
    "Mean",
];

/// The columns of Safe2Drive's Table 1 (also one row per model in `sds compare`).
pub(crate) const TABLE1_COLUMNS: [&str; 7] = [
    "DS",
    "SR(%)",
    "DS_safe",
    "Comfort",
    "Comfort (moving)",
    "Stationary(%)",
    "SDS",
];

/// Bench2Drive's main table: DS, SR (%), efficiency, comfortness (smoothness × 100), the five
/// ability rates (%) in the paper's column order, and their mean.
pub fn bench2drive_table(report: &Report) -> Grid {
    let rule = report.config.ability_rule.name();
    let mut g = Grid::new(
        &format!("Bench2Drive: closed-loop metrics and multi-ability (%), ability rule {rule}"),
        BENCH2DRIVE_COLUMNS,
    );
    let Some(b) = &report.summary.bench2drive else {
        return g;
    };
    let a = b.ability.clone().unwrap_or_default();
    g.row([
        num(b.driving_score, 2),
        num(b.success_rate, 2),
        num(b.efficiency, 2),
        pct(b.smoothness),
        pct(a.merging),
        pct(a.overtaking),
        pct(a.emergency_brake),
        pct(a.give_way),
        pct(a.traffic_signs),
        pct(a.mean),
    ]);
    if b.smoothness.is_none() && !any_telemetry(report) {
        g.note(NEEDS_TELEMETRY.replace("{what}", "Comfortness"));
    }
    if b.ability.is_none() {
        g.note("abilities need the route XML (routes)");
    } else {
        let counts: Vec<String> = b
            .ability_counts
            .0
            .iter()
            .map(|(n, c)| format!("{n} {}/{}", c.successes, c.routes))
            .collect();
        g.note(format!("ability successes/routes: {}", counts.join(", ")));
    }
    if !b.ability_missing.is_empty() {
        g.note(format!(
            "{} route(s) of the route set have no record (not in the ability rates): {}",
            b.ability_missing.len(),
            crate::input::warning::id_list(&b.ability_missing)
        ));
    }
    if let Some(note) = undecided_note(b) {
        g.note(note);
    }
    let stuck = &report.summary.scores.motion.stuck_routes;
    if !stuck.is_empty() {
        g.note(format!(
            "{} route(s) stood still for at least half of their frames: Comfortness counts a \
             standing chunk as comfortable (Table 1's Comfort (moving) leaves them out); see \
             summary.stuck_routes",
            stuck.len()
        ));
    }
    if !b.ability_marginal.is_empty() {
        g.note(format!(
            "Traffic_Signs: {} junction credit(s) decided within 0.15 of the threshold: \
             see summary.bench2drive.ability_marginal",
            b.ability_marginal.len()
        ));
    }
    g
}

/// The note on the Traffic_Signs routes whose junction credit is undecided (no map): how many,
/// their towns, and the bracket the Traffic Sign rate lies in (decided successes a floor, every
/// undecided credit a ceiling). `sds score`'s table and each run of `sds compare`'s say it.
pub fn undecided_note(b: &crate::aggregate::bench2drive::Bench2Drive) -> Option<String> {
    if b.ability_undecided.is_empty() {
        return None;
    }
    let mut towns: Vec<&str> = b
        .ability_undecided
        .iter()
        .filter_map(|u| u.town.as_deref())
        .collect();
    towns.sort_unstable();
    towns.dedup();
    // Each undecided route holds one junction credit (its only chance under b2d-0.0.4, its
    // second count under b2d-0.0.3): the decided rate is a floor, every credit a ceiling.
    let ts = b.ability_counts.get(crate::route::ability::TRAFFIC_SIGNS);
    let undecided = b.ability_undecided.len();
    let bracket = if ts.routes > 0 {
        let rate = |k: usize| 100.0 * k as f64 / ts.routes as f64;
        format!(
            "; Traffic Sign lies in [{:.2}, {:.2}] ({}/{} decided, up to {}/{} with every \
             undecided credit)",
            rate(ts.successes),
            rate(ts.successes + undecided),
            ts.successes,
            ts.routes,
            ts.successes + undecided,
            ts.routes
        )
    } else {
        String::new()
    };
    Some(format!(
        "Traffic_Signs under {}: {undecided} {}route(s) whose junction credit is undecided (no \
         map; towns {}) count as failed{bracket}; add the towns' maps (maps) to decide them: \
         see summary.bench2drive.ability_undecided",
        b.ability_rule,
        if b.ability_rule == "b2d-0.0.4" {
            "failed "
        } else {
            ""
        },
        towns.join(", ")
    ))
}

/// The note under a column left undefined (`-`) for want of telemetry.
const NEEDS_TELEMETRY: &str = "{what} - : no route has telemetry; they need each route's \
     metric_info.json (telemetry: the folder holding <save_name>/metric_info.json)";

/// True when some route of the report has its telemetry.
fn any_telemetry(report: &Report) -> bool {
    report
        .routes
        .iter()
        .any(|r| r.telemetry == crate::pipeline::outcome::TelemetryState::Ok)
}

/// The Safe2Drive Table 1 row: DS, SR, DS_safe, Comfort, SDS; beside Comfort, comfort over
/// the chunks the car drove and the share of frames it stood still (docs/SCORE.md §10.0).
pub fn table1(report: &Report) -> Grid {
    let s = &report.summary;
    let mut g = Grid::new("Safe2Drive Table 1: SafeDriving Score", TABLE1_COLUMNS);
    g.row([
        num(s.scores.driving_score, 2),
        num(s.scores.success_rate, 2),
        num(s.scores.mean_ds_safe, 2),
        num(s.scores.mean_comfort, 3),
        num(s.scores.motion.mean_comfort_moving, 3),
        pct(s.scores.motion.mean_stationary_share),
        num(s.scores.sds, 2),
    ]);
    // Under --allow-missing-telemetry a route without telemetry is no problem: not counted.
    let problems = if report.config.allow_missing_telemetry {
        String::new()
    } else {
        format!(", telemetry problems {}", s.telemetry_problems)
    };
    g.note(format!(
        "routes {} (found {}), comfort defined on {}{problems}, invalid records {}",
        s.routes, s.routes_found, s.scores.comfort_routes, s.invalid_records
    ));
    if s.scores.comfort_routes == 0 && !any_telemetry(report) {
        g.note(NEEDS_TELEMETRY.replace("{what}", "Comfort and SDS"));
    }
    g
}

fn table2_cells(label: &str, a: &Aggregates) -> Vec<String> {
    vec![
        label.to_string(),
        a.routes.to_string(),
        num(a.scores.driving_score, 2),
        num(a.scores.success_rate, 2),
        num(a.scores.collision_rate, 2),
        num(a.scores.mean_ds_safe, 2),
        num(a.scores.mean_comfort, 3),
        num(a.scores.motion.mean_comfort_moving, 3),
        pct(a.scores.motion.mean_stationary_share),
        num(a.scores.sds, 2),
    ]
}

/// The Table 2-style breakdown of the report's `groups`: routes, DS, SR, collision rate,
/// DS_safe, Comfort and SDS per group, and the Combined row. `None` without groups.
pub fn table2(report: &Report) -> Option<Grid> {
    let groups = report.groups.as_ref()?;
    let mut g = Grid::new(
        &format!("Safe2Drive Table 2-style breakdown by {}", groups.by),
        [
            groups.by,
            "routes",
            "DS",
            "SR(%)",
            "Coll.(%)",
            "DS_safe",
            "Comfort",
            "Comfort (moving)",
            "Stationary(%)",
            "SDS",
        ],
    );
    group_rows(&mut g, groups, table2_cells);
    Some(g)
}

/// One row per group, then the Combined row, each made by `cells` from its label and
/// aggregates.
fn group_rows(g: &mut Grid, groups: &Groups, cells: impl Fn(&str, &Aggregates) -> Vec<String>) {
    for r in &groups.rows {
        // Group labels come from the inputs (scenario names, label files): every cell is
        // escaped when the grid is rendered. A weather label lists the ids it stands for.
        let label = if r.keys.is_empty() {
            r.label.clone()
        } else {
            format!("{} ({})", r.label, r.keys.join(", "))
        };
        g.rows.push(cells(&label, &r.aggregates));
    }
    g.total = Some(cells("Combined", &groups.combined));
}

/// `k/n (r%)`: routes with the infraction / routes (rate).
fn rate_cell(k: usize, n: usize) -> String {
    if n == 0 {
        return format!("{k}/{n}");
    }
    format!("{k}/{n} ({:.1}%)", 100.0 * k as f64 / n as f64)
}

/// The Table 3-style breakdown by weather: per group, routes with each infraction / routes
/// (rate) for [`TABLE3_LISTS`] and `extra` lists. `None` unless the report is grouped by
/// weather.
pub fn table3(report: &Report, extra: &[String]) -> Option<Grid> {
    let groups = report.groups.as_ref()?;
    if groups.by != GroupBy::Weather.name() {
        return None;
    }
    let lists: Vec<(String, String)> = TABLE3_LISTS
        .iter()
        .map(|(l, h)| (l.to_string(), h.to_string()))
        .chain(extra.iter().map(|l| (l.clone(), l.clone())))
        .collect();
    let mut header = vec!["weather".to_string(), "routes".to_string()];
    header.extend(lists.iter().map(|(_, h)| h.clone()));
    let mut g = Grid::new(
        "Safe2Drive Table 3-style infractions by weather: routes with the infraction / routes (rate)",
        header,
    );
    let cells = |label: &str, a: &Aggregates| {
        let mut row = vec![label.to_string(), a.routes.to_string()];
        row.extend(
            lists
                .iter()
                .map(|(l, _)| rate_cell(a.infraction_routes.get(l), a.routes)),
        );
        row
    };
    group_rows(&mut g, groups, cells);
    Some(g)
}

/// Every table of a report, in order.
pub fn report_tables(report: &Report, options: &TableOptions) -> Vec<Grid> {
    let mut out = vec![bench2drive_table(report), table1(report)];
    out.extend(crate::report::protocol_table::protocol_table(report));
    out.extend(table2(report));
    out.extend(table3(report, &options.extra_infractions));
    // A subset's figures are not the benchmark's: every table says so.
    if let Some(s) = &report.route_subset {
        for g in &mut out {
            g.note(s.note());
        }
    }
    out
}

/// Renders tables one after the other, separated by a blank line.
pub fn render(grids: &[Grid], style: Style) -> String {
    grids
        .iter()
        .map(|g| g.render(style))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The report's tables in text (the `--format table` output).
///
/// ```
/// use monitor_host::report::table::{table, TableOptions};
/// use monitor_host::{demo, score_run, Inputs, Settings};
/// let dir = tempfile::tempdir()?;
/// let run = demo::write(dir.path())?;
/// let inputs = Inputs { telemetry: Some(run.telemetry), ..Inputs::new([run.results]) };
/// let report = score_run(&inputs, &Settings::default())?;
/// let text = table(&report, &TableOptions::default());
/// assert!(text.contains("Safe2Drive Table 1"));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn table(report: &Report, options: &TableOptions) -> String {
    render(&report_tables(report, options), Style::Text)
}
