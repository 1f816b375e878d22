//! `sds`: the SafeDriving Score tool. See `sds --help` and the crate docs of `monitor_host`.
//!
//! The binary is the library's [`sds_cli::main`] (shared with the Python package's
//! `sds` command); its docs list the exit codes.

fn main() {
    std::process::exit(sds_cli::main(std::env::args_os()));
}
