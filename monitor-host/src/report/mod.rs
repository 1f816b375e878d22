//! The report (`SDS-SPEC.md` v1.2 §10): the [`model`] a run produces and its renderings.
//!
//! | rendering | module |
//! |---|---|
//! | JSON (the full report) | [`json`] |
//! | CSV (one line per route) | [`mod@csv`] |
//! | tables (Bench2Drive's main table, Safe2Drive Tables 1-3, comparisons) | [`table`] |
//! | a table's text, Markdown and LaTeX renderings | [`grid`] |
//!
//! Strings from the inputs are escaped in one place, [`escape`], for the terminal and for CSV.

pub mod csv;
pub mod escape;
pub mod grid;
pub mod json;
pub mod model;
pub mod table;

pub use model::{Report, RouteReport};
