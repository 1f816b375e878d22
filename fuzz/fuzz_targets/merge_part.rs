//! `monitor_host::merge::read_part` on arbitrary bytes written to a file: never panics; an error
//! names the part. Seeds (fuzz/seeds.py): a real report of `sds score`, reports with fields out
//! of place, empty and non-JSON files (issue 47 finding 4: parts are read as every input is).
#![no_main]

use libfuzzer_sys::fuzz_target;
use monitor_host::merge::read_part;

fuzz_target!(|data: &[u8]| {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("part.json");
    std::fs::write(&path, data).expect("write");
    if let Err(e) = read_part(&path) {
        let msg = e.to_string();
        assert!(msg.contains("part.json"), "error does not name the part: {msg}");
    }
});
