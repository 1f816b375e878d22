//! Duplicate keys in a JSON document. JSON parsers (serde_json's `Value` among them) keep the
//! last of two equal keys without a word, so `"_checkpoint"` or `"records"` written twice, or a
//! record with two `"route_id"`s, would be read as whichever came last. Results files are checked
//! with [`first_duplicate_key`] before they are read; a duplicate refuses the file.
//!
//! ```
//! use monitor_host::input::json_keys::first_duplicate_key;
//! assert_eq!(first_duplicate_key(br#"{"a": 1, "b": {"c": [1, {"d": 2}]}}"#), Ok(None));
//! let doc = br#"{"_checkpoint": {"records": [{"route_id": "x", "route_id": "y"}]}}"#;
//! assert_eq!(
//!     first_duplicate_key(doc),
//!     Ok(Some("_checkpoint.records[0].route_id".to_string()))
//! );
//! ```

use std::collections::HashSet;
use std::fmt;

use serde::de::{self, DeserializeSeed, Deserializer, MapAccess, SeqAccess, Visitor};

/// The JSON path of the first key that appears twice in one object (`a.b[3].c`), `None` when
/// every object's keys are distinct.
///
/// # Errors
/// The parser's message when the bytes are not JSON (callers parse them again for a precise
/// error).
pub fn first_duplicate_key(bytes: &[u8]) -> Result<Option<String>, String> {
    let mut found = None;
    let mut path = Vec::new();
    let mut de = serde_json::Deserializer::from_slice(bytes);
    // A recursion limit of serde_json's own protects the stack on deeply nested input.
    let r = Walk {
        path: &mut path,
        found: &mut found,
    }
    .deserialize(&mut de);
    match (r, found) {
        (_, Some(p)) => Ok(Some(p)),
        (Ok(()), None) => Ok(None),
        (Err(e), None) => Err(e.to_string()),
    }
}

#[derive(Clone)]
enum Step {
    Key(String),
    Index(usize),
}

fn render(path: &[Step]) -> String {
    let mut s = String::new();
    for step in path {
        match step {
            Step::Key(k) => {
                if !s.is_empty() {
                    s.push('.');
                }
                s.push_str(k);
            }
            Step::Index(i) => s.push_str(&format!("[{i}]")),
        }
    }
    s
}

struct Walk<'a> {
    path: &'a mut Vec<Step>,
    found: &'a mut Option<String>,
}

impl<'de> DeserializeSeed<'de> for Walk<'_> {
    type Value = ();
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<(), D::Error> {
        d.deserialize_any(self)
    }
}

impl<'de> Visitor<'de> for Walk<'_> {
    type Value = ();

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("any JSON value")
    }

    fn visit_bool<E>(self, _: bool) -> Result<(), E> {
        Ok(())
    }
    fn visit_i64<E>(self, _: i64) -> Result<(), E> {
        Ok(())
    }
    fn visit_u64<E>(self, _: u64) -> Result<(), E> {
        Ok(())
    }
    fn visit_f64<E>(self, _: f64) -> Result<(), E> {
        Ok(())
    }
    fn visit_str<E>(self, _: &str) -> Result<(), E> {
        Ok(())
    }
    fn visit_unit<E>(self) -> Result<(), E> {
        Ok(())
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<(), A::Error> {
        let mut i = 0;
        loop {
            self.path.push(Step::Index(i));
            let more = seq.next_element_seed(Walk {
                path: self.path,
                found: self.found,
            })?;
            self.path.pop();
            if more.is_none() {
                return Ok(());
            }
            i += 1;
        }
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<(), A::Error> {
        let mut seen = HashSet::new();
        while let Some(key) = map.next_key::<String>()? {
            self.path.push(Step::Key(key.clone()));
            if !seen.insert(key) {
                *self.found = Some(render(self.path));
                return Err(de::Error::custom("duplicate key"));
            }
            map.next_value_seed(Walk {
                path: self.path,
                found: self.found,
            })?;
            self.path.pop();
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_the_duplicate() {
        let f = |s: &str| first_duplicate_key(s.as_bytes());
        assert_eq!(
            f(r#"{"_checkpoint": {}, "_checkpoint": {}}"#),
            Ok(Some("_checkpoint".into()))
        );
        assert_eq!(
            f(r#"{"_checkpoint": {"records": [], "records": [1]}}"#),
            Ok(Some("_checkpoint.records".into()))
        );
        assert_eq!(f(r#"[{"a": 1}, {"a": 2}]"#), Ok(None));
        assert_eq!(
            f(r#"[[{}], [{"x": 1, "x": 2}]]"#),
            Ok(Some("[1][0].x".into()))
        );
        // Escaped spellings of one key are one key.
        assert_eq!(f(r#"{"a": 1, "\u0061": 2}"#), Ok(Some("a".into())));
        assert!(f("{").is_err());
    }
}
