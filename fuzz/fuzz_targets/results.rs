//! `monitor_host::input::results_file::read_results` on arbitrary bytes written to a file: never panics; an error
//! names the file; a loaded set keeps every record of the file (none dropped).
#![no_main]

use libfuzzer_sys::fuzz_target;
use monitor_host::input::results_file as results;

fuzz_target!(|data: &[u8]| {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("endpoint.json");
    std::fs::write(&path, data).expect("write");
    match results::read_results(&path) {
        Ok(set) => {
            // Every element of `_checkpoint.records` is a route of the set, valid or not.
            // A leading byte order mark is skipped by the reader (issue 34, finding 9).
            let json = data.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(data);
            let value: serde_json::Value = serde_json::from_slice(json).expect("loaded => JSON");
            let n = value["_checkpoint"]["records"]
                .as_array()
                .map_or(0, Vec::len);
            assert_eq!(set.records.len(), n, "a record was lost");
            for (i, r) in set.records.iter().enumerate() {
                assert_eq!(r.index, i);
                if let Err(e) = &r.entry {
                    assert!(!e.reason.is_empty());
                }
            }
        }
        Err(e) => {
            let msg = e.to_string();
            assert!(
                msg.contains("endpoint.json"),
                "error does not name the file: {msg}"
            );
        }
    }
});
