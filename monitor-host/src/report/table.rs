//! The table rendering: the paper's Table 1 row and a Table 2-style breakdown.

use std::fmt::Write as _;

use crate::aggregate::groups::{self, GroupBy, Labels};
use crate::report::model::Report;

fn fmt_opt(x: Option<f64>, digits: usize) -> String {
    x.map_or_else(|| "-".to_string(), |v| format!("{v:.digits$}"))
}

/// The paper's Table 1 row and a Table 2-style breakdown.
pub fn table(report: &Report, group_by: GroupBy, labels: &Labels) -> String {
    let s = &report.summary;
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{:>8} {:>8} {:>8} {:>8} {:>8}",
        "DS", "SR", "DS_safe", "Comfort", "SDS"
    );
    let _ = writeln!(
        out,
        "{:>8} {:>8} {:>8} {:>8} {:>8}",
        fmt_opt(s.driving_score, 2),
        fmt_opt(s.success_rate, 2),
        fmt_opt(s.mean_ds_safe, 2),
        fmt_opt(s.mean_comfort, 3),
        fmt_opt(s.sds, 2)
    );
    let _ = writeln!(
        out,
        "routes {} (found {}), comfort defined on {}, telemetry problems {}, invalid records {}",
        s.routes, s.routes_found, s.comfort_routes, s.telemetry_problems, s.invalid_records
    );
    // Breakdown: routes, DS, SR, collision rate per group (denominator: routes of the group).
    let _ = writeln!(out);
    let _ = writeln!(
        out,
        "{:<40} {:>6} {:>8} {:>8} {:>8}",
        group_by.name(),
        "routes",
        "DS",
        "SR",
        "Coll."
    );
    for (k, g) in groups::group(&report.routes, group_by, labels) {
        // Group keys come from the inputs (scenario names, labels).
        let k = crate::report::escape::printable(&k);
        let _ = writeln!(
            out,
            "{k:<40} {:>6} {:>8.2} {:>8.2} {:>8.2}",
            g.routes,
            g.driving_score(),
            g.success_rate(),
            g.collision_rate()
        );
    }
    out
}
