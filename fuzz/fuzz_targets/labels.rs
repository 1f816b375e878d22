//! `monitor_host::input::labels::parse_labels` on arbitrary text: never panics; an error names the
//! file; a key given twice is always refused, never resolved silently; a CSV or JSON label is
//! never empty and never spans lines (issue 29: an unclosed quote no longer swallows the file);
//! and the labels, as group rows of a table, render in every style with no bidi, invisible or
//! control character let through raw.
#![no_main]

use libfuzzer_sys::fuzz_target;
use monitor_host::input::labels::{parse_labels, LabelsError};
use monitor_host::report::escape::is_hidden;
use monitor_host::report::grid::{Grid, Style};

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    match parse_labels(text, "labels.csv") {
        Ok(map) => {
            assert!(map.len() <= text.len());
            let body = text.trim_start_matches('\u{feff}').trim_start();
            if !body.starts_with('<') {
                for labels in map.values() {
                    assert!(!labels.is_empty());
                    for l in labels {
                        assert!(!l.trim().is_empty() && !l.contains('\n'), "label {l:?}");
                    }
                }
            }
            let mut g = Grid::new("labels", ["key", "label"]);
            for (k, labels) in map.iter().take(50) {
                for l in labels {
                    g.row([k.clone(), l.clone()]);
                }
            }
            for style in [Style::Text, Style::Markdown, Style::Latex] {
                let out = g.render(style);
                assert!(!out.chars().any(|c| is_hidden(c) && c != '\n'), "{style:?}");
            }
        }
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
