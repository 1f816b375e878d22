//! The pictures above the tables: the decomposition from DS to SDS as a waterfall
//! ([`crate::report::waterfall`]) and DS against DS_safe per route
//! ([`crate::report::route_chart`]), inline SVG. Their `data-` attributes carry the numbers drawn
//! so that the page's checks can compare them with the JSON report.

use super::page::escape;
use crate::report::{route_chart, waterfall, Report};

/// Writes the section (the waterfall only when the run has a decomposition).
pub(super) fn pictures(out: &mut String, report: &Report) {
    out.push_str("<h2 id=\"pictures\">From DS to SDS</h2>\n<div class=\"pictures\">\n");
    match &report.summary.scores.decomposition {
        Some(d) => {
            let steps: Vec<String> = waterfall::bars(d)
                .iter()
                .map(|b| format!("{}={}", b.label, b.to))
                .collect();
            out.push_str(&format!(
                "<figure id=\"waterfall\" data-ds=\"{}\" data-ds-safe=\"{}\" data-sds=\"{}\" data-steps=\"{}\">\n{}\n</figure>\n",
                d.ds,
                d.ds_safe,
                d.sds.map_or_else(String::new, |v| v.to_string()),
                escape(&steps.join(";")),
                waterfall::svg(d)
            ));
        }
        None => out.push_str(
            "<p class=\"note\" id=\"waterfall-none\">No decomposition: some route has no DS_safe (see its state).</p>\n",
        ),
    }
    let order: Vec<String> = route_chart::order(&report.routes)
        .iter()
        .map(|&i| {
            escape(
                report.routes[i]
                    .route_id
                    .as_deref()
                    .unwrap_or("<no route_id>"),
            )
        })
        .collect();
    out.push_str(&format!(
        "<figure id=\"route-chart\" data-routes=\"{}\" data-order=\"{}\">\n{}\n</figure>\n</div>\n",
        report.routes.len(),
        order.join(" "),
        route_chart::svg(&report.routes)
    ));
}
