//! `include/sds_monitor.h` must be what cbindgen generates from the code: regenerate it and
//! fail on a difference. `SDS_BLESS=1` rewrites the header instead.

use std::path::Path;

#[test]
fn header_matches_the_code() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let config = cbindgen::Config::from_file(dir.join("cbindgen.toml"))
        .unwrap_or_else(|e| panic!("bindings/c/cbindgen.toml: {e}"));
    let mut generated = Vec::new();
    cbindgen::Builder::new()
        .with_crate(dir)
        .with_config(config)
        .generate()
        .unwrap_or_else(|e| panic!("cbindgen failed on bindings/c/src: {e}"))
        .write(&mut generated);
    let path = dir.join("include/sds_monitor.h");
    if std::env::var_os("SDS_BLESS").is_some() {
        std::fs::write(&path, &generated).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        return;
    }
    let committed = std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    if committed != generated {
        let (a, b) = (
            String::from_utf8_lossy(&committed),
            String::from_utf8_lossy(&generated),
        );
        let first = a
            .lines()
            .zip(b.lines())
            .position(|(x, y)| x != y)
            .unwrap_or(a.lines().count().min(b.lines().count()));
        panic!(
            "bindings/c/include/sds_monitor.h is stale: it differs from cbindgen's output from \
             line {} on (committed: {:?}, generated: {:?}). Regenerate it with \
             `SDS_BLESS=1 cargo test -p sds-capi --release --test header` and commit it.",
            first + 1,
            a.lines().nth(first),
            b.lines().nth(first)
        );
    }
}
