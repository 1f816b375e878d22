//! The renderings of the report (docs/SCORE.md §13): the model a run produces
//! ([`Report`], built in [`crate::model::report`] from the rows of [`crate::route::row`])
//! turned into text. Nothing here computes a score.
//!
//! | rendering | module |
//! |---|---|
//! | the report (or a comparison) in a `--format`: the one dispatch | [`render`] |
//! | JSON (the full report) | [`json`] |
//! | CSV (one line per route) | [`mod@csv`] |
//! | tables (Bench2Drive's main table, Safe2Drive Tables 1-3) | [`table`] |
//! | the comparison's tables (per model, paired, flips; docs/SCORE.md §10.3) | [`compare_table`] |
//! | the scoring-protocol table (docs/PROTOCOLS.md) | [`protocol_table`] |
//! | a table's text, Markdown and LaTeX renderings | [`grid`] |
//! | a collision trace as a figure (SVG, docs/SCORE.md §14.4) | [`figure`] |
//! | the comparison's forest plot (SVG, docs/SCORE.md §10.3) | [`forest`] |
//! | a collision trace as CSV | [`trace_csv`] |
//! | the decomposition from DS to SDS as a waterfall (SVG) | [`waterfall`] |
//! | DS and DS_safe per route (SVG) | [`route_chart`] |
//! | the whole run (or runs side by side) as one HTML page | [`html`] |
//! | `sds frames`' JSON lines | [`frames`] |
//! | long tables: routes, events, frames as CSV (docs/TABLES-SCHEMA.md) | [`long_tables`] |
//!
//! Strings from the inputs are escaped in one place, [`escape`], for the terminal and for CSV.

pub mod compare_table;
pub mod csv;
pub mod escape;
pub mod figure;
pub mod forest;
pub mod frames;
pub mod grid;
pub mod html;
pub mod json;
pub mod long_tables;
pub mod protocol_csv;
pub mod protocol_table;
pub mod render;
pub mod rerun_list;
pub mod route_chart;
pub mod seeds_table;
pub mod status;
pub mod sweep_table;
pub mod table;
pub mod trace_csv;
pub mod waterfall;

pub use crate::model::report::Report;
pub use crate::route::row::RouteReport;
