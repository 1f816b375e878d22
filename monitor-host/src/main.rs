//! `sds`: the SafeDriving Score tool.
fn main() {}
