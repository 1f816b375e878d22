//! `monitor_host::input::labels::parse_labels` on arbitrary text: never panics; an error names the
//! file; a key given twice is always refused, never resolved silently.
#![no_main]

use libfuzzer_sys::fuzz_target;
use monitor_host::input::labels::{parse_labels, LabelsError};

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    match parse_labels(text, "labels.csv") {
        Ok(map) => assert!(map.len() <= text.len()),
        Err(e) => {
            let msg = e.to_string();
            assert!(msg.contains("labels.csv"), "error does not name the file: {msg}");
            if let LabelsError::Duplicate { key, .. } = &e {
                // `key` is a path (`outer.inner`, `list[2].k`) when the duplicate is nested: its
                // last step, unescaped, is what the text must hold.
                let last = key.rsplit(['.', ']']).next().unwrap_or(key);
                assert!(text.contains(last) || text.contains('\\'), "{key} not in the text");
            }
        }
    }
});
