//! `sds`: the SafeDriving Score tool. See `sds --help` and the crate docs of `monitor_host`.
//!
//! The binary is the library's [`monitor_host::cli::main`] (shared with the Python package's
//! `sds` command).
//!
//! Exit codes: 0 success; 1 an input could not be read or the output not written (no report);
//! 2 usage error; 3 the report was written but some route has a problem (missing or invalid
//! telemetry without `--allow-missing-telemetry`, an invalid record, or a streaming/batch
//! disagreement) — every such route is in the report with its state.

fn main() {
    std::process::exit(monitor_host::cli::main(std::env::args_os()));
}
