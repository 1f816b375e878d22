//! One test binary for the property tests of the core and the host (ripgrep's `tests/` shape):
//! each module holds one property and its oracle. Proptest keeps the failing cases it found in
//! `../proptest-regressions/<module>.txt` (its default place beside the folder holding
//! `main.rs`) and runs them again first.

mod link_checker;
mod map_reader_never_panics;
mod metric_info_fast_path;
mod nearest_vs_scan;
mod parsers_never_panic;
mod streaming_vs_batch;
