//! Renderings of a watch round's [`RoundStatus`] (docs/USAGE.md §8): one JSON line (`sds watch
//! --status-json`), and the short duration of the estimate of the time left.

use crate::model::status::RoundStatus;

impl RoundStatus {
    /// The line as one JSON object (serde_json), with every control, bidirectional and invisible
    /// format character written as a JSON `\uXXXX` escape: valid JSON that cannot rewrite the
    /// terminal it is printed on.
    ///
    /// ```
    /// let s = monitor_host::RoundStatus { last_route: Some("R\u{202e}1".into()),
    ///                                            ..Default::default() };
    /// let line = s.json();
    /// assert!(line.contains(r#""last_route":"R\u202e1""#));
    /// let back: serde_json::Value = serde_json::from_str(&line)?;
    /// assert_eq!(back["last_route"], "R\u{202e}1");
    /// # Ok::<(), serde_json::Error>(())
    /// ```
    pub fn json(&self) -> String {
        let raw = serde_json::to_string(self).unwrap_or_default();
        let mut out = String::with_capacity(raw.len());
        for c in raw.chars() {
            if crate::report::escape::is_hidden(c) {
                let mut units = [0u16; 2];
                for u in c.encode_utf16(&mut units) {
                    out.push_str(&format!("\\u{u:04x}"));
                }
            } else {
                out.push(c);
            }
        }
        out
    }
}

pub use crate::model::duration::duration_text;
