//! The scoring protocols' CSV columns (docs/PROTOCOLS.md), appended to the per-route and
//! per-group CSV when protocols are asked: per route `<id>_penalty`, `<id>_score`,
//! `<id>_success`; per group `<id>_driving_score`, `<id>_route_completion`,
//! `<id>_infraction_score`, `<id>_success_rate`, and `f2d_hm`.
//!
//! ```
//! use monitor_host::route::protocol::Protocol;
//! use monitor_host::report::protocol_csv::{group_columns, route_columns};
//! assert_eq!(route_columns(&[Protocol::Lb21]), ["lb2.1_penalty", "lb2.1_score", "lb2.1_success"]);
//! assert_eq!(group_columns(&[Protocol::F2d]).last().map(String::as_str), Some("f2d_hm"));
//! assert!(route_columns(&[]).is_empty());
//! ```

use crate::route::protocol::aggregate::ProtocolScores;
use crate::route::protocol::route::RouteProtocols;
use crate::route::protocol::Protocol;

/// A float as JSON prints it; empty when absent.
fn num(x: Option<f64>) -> String {
    x.and_then(|v| serde_json::to_string(&v).ok())
        .unwrap_or_default()
}

/// The per-route columns of `asked`.
pub fn route_columns(asked: &[Protocol]) -> Vec<String> {
    asked
        .iter()
        .flat_map(|p| ["penalty", "score", "success"].map(|c| format!("{}_{c}", p.id())))
        .collect()
}

/// A route's cells under [`route_columns`] (empty cells where it has none).
pub fn route_cells(protocols: Option<&RouteProtocols>, asked: &[Protocol]) -> Vec<String> {
    asked
        .iter()
        .flat_map(|p| match protocols.and_then(|r| r.get(*p)) {
            Some(s) => [num(s.penalty), num(Some(s.score)), s.success.to_string()],
            None => [String::new(), String::new(), String::new()],
        })
        .collect()
}

/// The per-group columns of `asked`.
pub fn group_columns(asked: &[Protocol]) -> Vec<String> {
    let mut out = Vec::new();
    for p in asked {
        for c in [
            "driving_score",
            "route_completion",
            "infraction_score",
            "success_rate",
        ] {
            out.push(format!("{}_{c}", p.id()));
        }
        if *p == Protocol::F2d {
            out.push("f2d_hm".into());
        }
    }
    out
}

/// A group's cells under [`group_columns`].
pub fn group_cells(scores: Option<&ProtocolScores>, asked: &[Protocol]) -> Vec<String> {
    let mut out = Vec::new();
    for p in asked {
        let a = scores.and_then(|s| s.get(*p)).copied().unwrap_or_default();
        out.extend(
            [
                a.driving_score,
                a.route_completion,
                a.infraction_score,
                a.success_rate,
            ]
            .map(num),
        );
        if *p == Protocol::F2d {
            out.push(num(a.hm));
        }
    }
    out
}
