//! `sds`: the SafeDriving Score tool. See `sds --help` and the crate docs of `monitor_host`.
fn main() {
    std::process::exit(monitor_host::cli::main());
}
