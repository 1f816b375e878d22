//! `monitor_host::Settings::set` on arbitrary names and values: never panics; a setting it
//! accepts leaves the whole valid, and a refused one leaves the settings unchanged.
#![no_main]

use libfuzzer_sys::fuzz_target;
use monitor_host::Settings;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let mut s = Settings::default();
    for line in text.lines() {
        let before = s.clone();
        match line.split_once('=') {
            Some((name, value)) => match s.set(name, value) {
                Ok(()) => assert!(s.validate().is_ok(), "{line}: accepted but invalid"),
                Err(_) => assert!(s == before, "{line}: refused but changed"),
            },
            None => assert!(s.apply(&[line.to_string()]).is_err()),
        }
    }
});
