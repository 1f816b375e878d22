//! `monitor_host::input::collision::parse_collision` on arbitrary strings: never panics; an accepted
//! string has a non-empty type and finite coordinates; an error quotes the input.
#![no_main]

use libfuzzer_sys::fuzz_target;
use monitor_host::input::collision::{is_workzone, parse_collision};

fuzz_target!(|data: &[u8]| {
    let Ok(s) = std::str::from_utf8(data) else {
        return;
    };
    match parse_collision(s) {
        Ok(c) => {
            assert!(!c.type_id.is_empty());
            assert!(!c.type_id.contains(char::is_whitespace));
            if let Some(l) = c.location {
                assert!(l.iter().all(|v| v.is_finite()));
            }
            let _ = is_workzone(&c.type_id);
        }
        Err(e) => assert_eq!(e.input, s),
    }
});
