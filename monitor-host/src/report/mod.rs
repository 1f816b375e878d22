//! The report (`SDS-SPEC.md` v1.2 §10): the [`model`] a run produces and its renderings.
//!
//! | rendering | module |
//! |---|---|
//! | JSON (the full report) | [`json`] |
//! | CSV (one line per route) | [`mod@csv`] |
//! | table (Table 1 row, Table 2-style breakdown) | [`table`] |
//!
//! Strings from the inputs are escaped in one place, [`escape`], for the terminal and for CSV.

pub mod csv;
pub mod escape;
pub mod json;
pub mod model;
pub mod table;

pub use model::{Report, RouteReport};
