//! The sweep's table (`sds compare --sweep`, docs/SCORE.md §10.4): one row per point of the grid with
//! each swept setting's value and every model's SDS and rank there; notes give each model's SDS
//! range and each pair's order over the grid.

use crate::report::grid::Grid;
use crate::stats::Comparison;

/// The sweep's table, or nothing without a sweep.
///
/// ```
/// use monitor_host::report::sweep_table::sweep_tables;
/// use monitor_host::settings::defs::Value;
/// use monitor_host::stats::sweep::report;
/// use monitor_host::stats::{compare, CompareOptions, Model, NamedRun};
/// use monitor_host::{demo, score_run, Inputs, Settings};
/// let dir = tempfile::tempdir()?;
/// let run = demo::write(dir.path())?;
/// let inputs = Inputs { telemetry: Some(run.telemetry), ..Inputs::new([run.results]) };
/// let r = score_run(&inputs, &Settings::default())?;
/// let m = |n: &str| Model { name: n.into(), runs: vec![NamedRun { name: n.into(), report: r.clone() }] };
/// let mut c = compare(&[m("a"), m("b")], &CompareOptions::default())?;
/// assert!(sweep_tables(&c).is_empty());
/// let at = vec![("slack".to_string(), Value::F32(0.8))];
/// c.sweep = Some(report(&["slack".into()], &["a".into(), "b".into()],
///     vec![(at, vec![[Some(60.0), Some(0.9), Some(54.0)], [Some(50.0), Some(0.9), Some(45.0)]])]));
/// let text = monitor_host::report::table::render(&sweep_tables(&c), monitor_host::report::grid::Style::Text);
/// assert!(text.contains("54.00 (1)") && text.contains("45.00 (2)"), "{text}");
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn sweep_tables(c: &Comparison) -> Vec<Grid> {
    let Some(s) = &c.sweep else {
        return Vec::new();
    };
    let models: Vec<&str> = s
        .points
        .first()
        .map(|p| p.models.iter().map(|m| m.model.as_str()).collect())
        .unwrap_or_default();
    let header: Vec<String> = std::iter::once("point".to_string())
        .chain(s.settings.iter().cloned())
        .chain(
            models
                .iter()
                .flat_map(|m| [format!("{m} DS_safe"), format!("{m} SDS (rank)")]),
        )
        .collect();
    let mut g = Grid::new(
        &format!(
            "Sweep: every model's DS_safe, SDS and rank at each of {} point(s) of {}",
            s.points.len(),
            s.settings.join(" x ")
        ),
        header,
    );
    for (i, p) in s.points.iter().enumerate() {
        g.row(
            std::iter::once(i.to_string())
                .chain(p.values.iter().map(|(_, v)| v.text()))
                .chain(p.models.iter().flat_map(|m| {
                    [
                        m.ds_safe.map_or_else(|| "-".into(), |x| format!("{x:.2}")),
                        match (m.sds, m.rank) {
                            (Some(x), Some(r)) => format!("{x:.2} ({r})"),
                            _ => "-".to_string(),
                        },
                    ]
                })),
        );
    }
    for r in &s.ranges {
        if let (Some(lo), Some(hi)) = (r.sds_min, r.sds_max) {
            g.note(format!("{}: SDS {lo:.2} to {hi:.2} over the grid", r.model));
        } else {
            g.note(format!(
                "{}: no SDS at some point (comfort undefined: it needs telemetry)",
                r.model
            ));
        }
    }
    // Without any SDS (no telemetry, so no comfort) there is no order to hold.
    let none = s.ranges.iter().all(|r| r.sds_min.is_none());
    for p in s.pairs.iter().filter(|_| !none) {
        if p.order_stable {
            g.note(format!("{} vs {}: the same order at every point", p.a, p.b));
        } else {
            let at: Vec<String> = p.flips.iter().map(ToString::to_string).collect();
            g.note(format!(
                "{} vs {}: the order changes at point(s) {} (from the point before)",
                p.a,
                p.b,
                at.join(", ")
            ));
        }
    }
    if none {
        g.note(
            "no model has an SDS: the order by SDS is unknown at every point (DS_safe still moves)",
        );
    }
    g.note("rank = 1 + the models with a strictly greater SDS at that point; the other settings as given");
    vec![g]
}
