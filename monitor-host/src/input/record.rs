//! One route record of an evaluator results file (docs/SCORE.md §2.1, docs/SCORE.md §9 success rule):
//! its infraction lists, scores and meta, validated field by field.
//!
//! ```
//! use monitor_host::input::record::Record;
//! let r = Record::from_value(&serde_json::json!({
//!     "route_id": "RouteScenario_3564_rep0", "scenario_name": "InvadingTurn_1",
//!     "status": "Completed", "infractions": {},
//!     "scores": {"score_route": 100, "score_penalty": 1.0, "score_composed": 100.0}}))?;
//! assert_eq!((r.xml_id(), r.scenario_type()), (Some("3564"), "InvadingTurn"));
//! assert!(r.is_success());
//! let bad = Record::from_value(&serde_json::json!({"route_id": "x"})).unwrap_err();
//! assert_eq!(bad.reason, "field status: missing");
//! # Ok::<(), monitor_host::input::record::InvalidRecord>(())
//! ```

use std::path::PathBuf;

use serde_json::{Map, Value};

/// The 12 infraction lists of a Leaderboard 2.0 record, in the spec's order (docs/SCORE.md §2.1).
pub const KNOWN_LISTS: [&str; 12] = [
    "collisions_pedestrian",
    "collisions_vehicle",
    "collisions_layout",
    "red_light",
    "stop_infraction",
    "outside_route_lanes",
    "min_speed_infractions",
    "yield_emergency_vehicle_infractions",
    "scenario_timeouts",
    "route_dev",
    "vehicle_blocked",
    "route_timeout",
];

/// The one infraction list that does not prevent a success (docs/SCORE.md §9).
pub const MIN_SPEED_LIST: &str = "min_speed_infractions";

/// A record's infraction lists: the 12 known lists by name plus any unknown extra lists, the
/// latter in file order. A known list absent from the file is empty.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Infractions {
    known: [Vec<String>; 12],
    unknown: Vec<(String, Vec<String>)>,
}

impl Infractions {
    /// No infractions at all.
    pub fn new() -> Self {
        Self::default()
    }

    /// Builds the lists from `(name, entries)` pairs; unknown names are kept in the given order.
    /// A name given twice appends to the earlier list.
    pub fn from_lists<I, N>(lists: I) -> Self
    where
        I: IntoIterator<Item = (N, Vec<String>)>,
        N: Into<String>,
    {
        let mut inf = Self::default();
        for (name, entries) in lists {
            inf.push_list(name.into(), entries);
        }
        inf
    }

    fn push_list(&mut self, name: String, mut entries: Vec<String>) {
        if let Some(i) = KNOWN_LISTS.iter().position(|k| *k == name) {
            self.known[i].append(&mut entries);
        } else if let Some((_, list)) = self.unknown.iter_mut().find(|(n, _)| *n == name) {
            list.append(&mut entries);
        } else {
            self.unknown.push((name, entries));
        }
    }

    /// [`Infractions::from_lists`] of string slices (the tests' shorthand).
    #[cfg(test)]
    pub(crate) fn of(lists: &[(&str, &[&str])]) -> Self {
        Self::from_lists(
            lists
                .iter()
                .map(|(n, l)| (*n, l.iter().map(|s| s.to_string()).collect())),
        )
    }

    /// The entries of list `name` (known or unknown); an empty slice if the list is absent.
    pub fn list(&self, name: &str) -> &[String] {
        if let Some(i) = KNOWN_LISTS.iter().position(|k| *k == name) {
            return &self.known[i];
        }
        self.unknown
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, l)| l.as_slice())
            .unwrap_or(&[])
    }

    /// The unknown extra lists, in file order.
    pub fn unknown(&self) -> impl Iterator<Item = (&str, &[String])> {
        self.unknown.iter().map(|(n, l)| (n.as_str(), l.as_slice()))
    }

    /// Every list: the 12 known ones in [`KNOWN_LISTS`] order, then the unknown ones.
    pub fn all(&self) -> impl Iterator<Item = (&str, &[String])> {
        KNOWN_LISTS
            .iter()
            .zip(self.known.iter())
            .map(|(n, l)| (*n, l.as_slice()))
            .chain(self.unknown())
    }

    /// True when every list except `min_speed_infractions` is empty, unknown lists included
    /// (the infraction half of the §8 success rule).
    pub fn clean_except_min_speed(&self) -> bool {
        self.all()
            .all(|(name, list)| name == MIN_SPEED_LIST || list.is_empty())
    }
}

/// `meta` of a record: lengths in metres, durations in seconds. Absent or null fields are `None`.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Meta {
    /// `meta.route_length` (m).
    pub route_length: Option<f64>,
    /// `meta.duration_game` (simulated s).
    pub duration_game: Option<f64>,
    /// `meta.duration_system` (wall-clock s).
    pub duration_system: Option<f64>,
}

/// One validated route record (docs/SCORE.md §2.1). Unknown extra keys are ignored.
#[derive(Debug, Clone, PartialEq)]
pub struct Record {
    /// `RouteScenario_<xmlid>_rep<k>`.
    pub route_id: String,
    /// e.g. `ConstructionObstacle_1`; empty when the record has none.
    pub scenario_name: String,
    /// Weather preset id; numbers in the file are turned into strings.
    pub weather_id: Option<String>,
    /// `<route_id>_<Town>_<scenario_name>_<weather_id>_<timestamp>`: the telemetry folder name.
    pub save_name: Option<String>,
    /// e.g. `Town12`.
    pub town_name: Option<String>,
    /// `Completed`, `Perfect` or `Failed - <reason>`.
    pub status: String,
    /// The infraction lists.
    pub infractions: Infractions,
    /// `scores.score_route` (0..100).
    pub score_route: f64,
    /// `scores.score_penalty` (authoritative, docs/SCORE.md §9).
    pub score_penalty: f64,
    /// `scores.score_composed`.
    pub score_composed: f64,
    /// `meta`.
    pub meta: Meta,
}

impl Record {
    /// `<xmlid>` of `RouteScenario_<xmlid>_rep<k>`, or `None` when `route_id` has another form.
    pub fn xml_id(&self) -> Option<&str> {
        let rest = self.route_id.strip_prefix("RouteScenario_")?;
        let (id, rep) = rest.rsplit_once("_rep")?;
        let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
        (digits(id) && digits(rep)).then_some(id)
    }

    /// The scenario type: `scenario_name` without its trailing `_<N>` suffix
    /// (`ConstructionObstacle_1` → `ConstructionObstacle`). A name without such a suffix is
    /// returned whole.
    pub fn scenario_type(&self) -> &str {
        match self.scenario_name.rsplit_once('_') {
            Some((head, n)) if !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()) => head,
            _ => &self.scenario_name,
        }
    }

    /// docs/SCORE.md §9 success: status `Completed` or `Perfect`, and every infraction list except
    /// `min_speed_infractions` empty (unknown extra lists included).
    pub fn is_success(&self) -> bool {
        matches!(self.status.as_str(), "Completed" | "Perfect")
            && self.infractions.clean_except_min_speed()
    }

    /// Validates one record value. The error's `reason` names the offending field, e.g.
    /// `field scores.score_route: expected a number, got string`.
    pub fn from_value(value: &Value) -> Result<Record, InvalidRecord> {
        let Some(obj) = value.as_object() else {
            return Err(InvalidRecord {
                route_id: None,
                reason: format!("record: expected an object, got {}", kind(value)),
            });
        };
        let route_id = obj
            .get("route_id")
            .and_then(Value::as_str)
            .map(String::from);
        let fail = |reason: String| InvalidRecord {
            route_id: route_id.clone(),
            reason,
        };
        let route_id_s = req_str(obj, "route_id", "route_id").map_err(fail)?;
        let status = req_str(obj, "status", "status").map_err(fail)?;
        let scores = match obj.get("scores") {
            None => return Err(fail(missing("scores"))),
            Some(Value::Object(m)) => m,
            Some(v) => return Err(fail(wrong("scores", "an object", v))),
        };
        let score_route = req_num(scores, "score_route", "scores.score_route").map_err(fail)?;
        let score_penalty =
            req_num(scores, "score_penalty", "scores.score_penalty").map_err(fail)?;
        let score_composed =
            req_num(scores, "score_composed", "scores.score_composed").map_err(fail)?;
        // Out-of-range scores would reach the aggregates (DS_safe 500, sums overflowing to inf).
        in_range(score_route, "scores.score_route", 100.0).map_err(fail)?;
        in_range(score_penalty, "scores.score_penalty", 1.0).map_err(fail)?;
        in_range(score_composed, "scores.score_composed", 100.0).map_err(fail)?;
        let infractions = match obj.get("infractions") {
            None => return Err(fail(missing("infractions"))),
            Some(Value::Object(m)) => infraction_lists(m).map_err(fail)?,
            Some(v) => return Err(fail(wrong("infractions", "an object", v))),
        };
        let scenario_name = opt_str(obj, "scenario_name", "scenario_name")
            .map_err(fail)?
            .unwrap_or_default();
        let weather_id = match obj.get("weather_id") {
            None | Some(Value::Null) => None,
            Some(Value::String(s)) => Some(s.clone()),
            Some(Value::Number(n)) => Some(number_to_id(n)),
            Some(v) => return Err(fail(wrong("weather_id", "a string or number", v))),
        };
        let save_name = opt_str(obj, "save_name", "save_name").map_err(fail)?;
        let town_name = opt_str(obj, "town_name", "town_name").map_err(fail)?;
        let meta = match obj.get("meta") {
            None | Some(Value::Null) => Meta::default(),
            Some(Value::Object(m)) => Meta {
                route_length: opt_num(m, "route_length", "meta.route_length").map_err(fail)?,
                duration_game: opt_num(m, "duration_game", "meta.duration_game").map_err(fail)?,
                duration_system: opt_num(m, "duration_system", "meta.duration_system")
                    .map_err(fail)?,
            },
            Some(v) => return Err(fail(wrong("meta", "an object", v))),
        };
        Ok(Record {
            route_id: route_id_s,
            scenario_name,
            weather_id,
            save_name,
            town_name,
            status,
            infractions,
            score_route,
            score_penalty,
            score_composed,
            meta,
        })
    }
}

/// A record that failed validation; kept so that it is reported, never dropped.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct InvalidRecord {
    /// The record's `route_id` when it has a string one.
    pub route_id: Option<String>,
    /// What is wrong, naming the field (`field scores.score_route: expected a number, got string`).
    pub reason: String,
}

impl std::error::Error for InvalidRecord {}

impl std::fmt::Display for InvalidRecord {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match &self.route_id {
            Some(id) => write!(f, "route {id}: {}", self.reason),
            None => write!(f, "{}", self.reason),
        }
    }
}

/// One record as read, with where it came from.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadedRecord {
    /// The file it came from.
    pub source: PathBuf,
    /// Its position in that file's `_checkpoint.records` (0-based).
    pub index: usize,
    /// How many records that file holds (telemetry beside the file is only used when it is 1).
    pub records_in_file: usize,
    /// The validated record, or why it is invalid.
    pub entry: Result<Record, InvalidRecord>,
}

fn infraction_lists(m: &Map<String, Value>) -> Result<Infractions, String> {
    let mut inf = Infractions::default();
    for (name, v) in m {
        let field = format!("infractions.{name}");
        let Value::Array(items) = v else {
            return Err(wrong(&field, "an array of strings", v));
        };
        let mut entries = Vec::with_capacity(items.len());
        for (i, item) in items.iter().enumerate() {
            match item {
                Value::String(s) => entries.push(s.clone()),
                other => return Err(wrong(&format!("{field}[{i}]"), "a string", other)),
            }
        }
        inf.push_list(name.clone(), entries);
    }
    Ok(inf)
}

fn number_to_id(n: &serde_json::Number) -> String {
    if let Some(u) = n.as_u64() {
        return u.to_string();
    }
    if let Some(i) = n.as_i64() {
        return i.to_string();
    }
    match n.as_f64() {
        Some(f) if f.fract() == 0.0 && f.abs() < 1e15 => format!("{f:.0}"),
        _ => n.to_string(),
    }
}

pub(crate) fn kind(v: &Value) -> &'static str {
    match v {
        Value::Null => "null",
        Value::Bool(_) => "boolean",
        Value::Number(_) => "number",
        Value::String(_) => "string",
        Value::Array(_) => "array",
        Value::Object(_) => "object",
    }
}

pub(crate) fn expected(what: &str, got: &Value) -> String {
    format!("expected {what}, got {}", kind(got))
}

fn missing(field: &str) -> String {
    format!("field {field}: missing")
}

fn wrong(field: &str, what: &str, got: &Value) -> String {
    format!("field {field}: {}", expected(what, got))
}

fn req_str(m: &Map<String, Value>, key: &str, field: &str) -> Result<String, String> {
    match m.get(key) {
        None => Err(missing(field)),
        Some(Value::String(s)) => Ok(s.clone()),
        Some(v) => Err(wrong(field, "a string", v)),
    }
}

fn opt_str(m: &Map<String, Value>, key: &str, field: &str) -> Result<Option<String>, String> {
    match m.get(key) {
        None | Some(Value::Null) => Ok(None),
        Some(Value::String(s)) => Ok(Some(s.clone())),
        Some(v) => Err(wrong(field, "a string", v)),
    }
}

/// A score must lie in `0..=max` (finite: JSON numbers always are, but `1e999` is not JSON).
fn in_range(x: f64, field: &str, max: f64) -> Result<(), String> {
    if (0.0..=max).contains(&x) {
        Ok(())
    } else {
        Err(format!("field {field}: {x:?} is outside 0..={max}"))
    }
}

/// How far `score_composed` may be from `score_route * score_penalty`: the evaluator stores the
/// penalty rounded to 6 decimals but multiplies the unrounded one (up to 100 * 5e-7 apart), then
/// rounds the product to 6 decimals.
pub const COMPOSED_TOLERANCE: f64 = 1e-4;

impl Record {
    /// `score_composed` differs from `score_route * score_penalty` by more than
    /// [`COMPOSED_TOLERANCE`]: the record was edited or written by another tool. A warning only:
    /// SDS uses `score_route` and `score_penalty`, never `score_composed`.
    ///
    /// ```
    /// use monitor_host::input::record::Record;
    /// let mut r = Record::from_value(&serde_json::json!({"route_id": "x", "status": "Completed",
    ///     "infractions": {}, "scores": {"score_route": 76.28, "score_penalty": 0.612855,
    ///     "score_composed": 46.74855}}))?;
    /// assert!(!r.composed_mismatch());
    /// r.score_composed = 50.0;
    /// assert!(r.composed_mismatch());
    /// # Ok::<(), monitor_host::input::record::InvalidRecord>(())
    /// ```
    pub fn composed_mismatch(&self) -> bool {
        (self.score_composed - self.score_route * self.score_penalty).abs() > COMPOSED_TOLERANCE
    }
}

fn req_num(m: &Map<String, Value>, key: &str, field: &str) -> Result<f64, String> {
    match m.get(key) {
        None => Err(missing(field)),
        Some(v) => v.as_f64().ok_or_else(|| wrong(field, "a number", v)),
    }
}

fn opt_num(m: &Map<String, Value>, key: &str, field: &str) -> Result<Option<f64>, String> {
    match m.get(key) {
        None | Some(Value::Null) => Ok(None),
        Some(v) => v
            .as_f64()
            .map(Some)
            .ok_or_else(|| wrong(field, "a number", v)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn good() -> Value {
        json!({
            "index": 0,
            "route_id": "RouteScenario_24206_rep3",
            "scenario_name": "ConstructionObstacle_12",
            "weather_id": "7",
            "save_name": "RouteScenario_24206_rep3_Town12_ConstructionObstacle_12_7_06_17_06_49_04",
            "status": "Completed",
            "num_infractions": 1,
            "infractions": {
                "collisions_layout": [],
                "min_speed_infractions": ["Average speed is 80.5% of the surrounding traffic's one"],
                "route_timeout": []
            },
            "scores": {"score_route": 100, "score_penalty": 1.0, "score_composed": 100.0},
            "meta": {"route_length": 102.063, "duration_game": 200.05, "duration_system": null},
            "town_name": "Town12"
        })
    }

    fn reason_of(v: &Value) -> String {
        Record::from_value(v).expect_err("must be invalid").reason
    }

    #[test]
    fn valid_record_fields() {
        let r = Record::from_value(&good()).unwrap();
        assert_eq!(r.route_id, "RouteScenario_24206_rep3");
        assert_eq!(r.xml_id(), Some("24206"));
        assert_eq!(r.scenario_type(), "ConstructionObstacle");
        assert_eq!(r.weather_id.as_deref(), Some("7"));
        assert_eq!(r.town_name.as_deref(), Some("Town12"));
        assert_eq!(r.score_route, 100.0);
        assert_eq!(r.meta.route_length, Some(102.063));
        assert_eq!(r.meta.duration_system, None);
        assert_eq!(r.infractions.list("min_speed_infractions").len(), 1);
        assert!(r.infractions.list("collisions_vehicle").is_empty());
        assert!(r.infractions.list("no_such_list").is_empty());
        assert!(r.is_success());
    }

    #[test]
    fn weather_id_numbers_and_null() {
        let mut v = good();
        v["weather_id"] = json!(23);
        assert_eq!(
            Record::from_value(&v).unwrap().weather_id.as_deref(),
            Some("23")
        );
        v["weather_id"] = json!(5.0);
        assert_eq!(
            Record::from_value(&v).unwrap().weather_id.as_deref(),
            Some("5")
        );
        v["weather_id"] = Value::Null;
        assert_eq!(Record::from_value(&v).unwrap().weather_id, None);
        v["weather_id"] = json!([1]);
        assert_eq!(
            reason_of(&v),
            "field weather_id: expected a string or number, got array"
        );
    }

    #[test]
    fn save_name_may_be_missing() {
        let mut v = good();
        v.as_object_mut().unwrap().remove("save_name");
        v.as_object_mut().unwrap().remove("meta");
        let r = Record::from_value(&v).unwrap();
        assert_eq!(r.save_name, None);
        assert_eq!(r.meta, Meta::default());
    }

    #[test]
    fn invalid_records_name_the_field() {
        let mut v = good();
        v["scores"]["score_route"] = json!("100");
        let e = Record::from_value(&v).unwrap_err();
        assert_eq!(e.route_id.as_deref(), Some("RouteScenario_24206_rep3"));
        assert_eq!(
            e.reason,
            "field scores.score_route: expected a number, got string"
        );

        let mut v = good();
        v["scores"].as_object_mut().unwrap().remove("score_penalty");
        assert_eq!(reason_of(&v), "field scores.score_penalty: missing");

        let mut v = good();
        v["scores"]["score_composed"] = Value::Null;
        assert_eq!(
            reason_of(&v),
            "field scores.score_composed: expected a number, got null"
        );

        let mut v = good();
        v.as_object_mut().unwrap().remove("route_id");
        let e = Record::from_value(&v).unwrap_err();
        assert_eq!(e.route_id, None);
        assert_eq!(e.reason, "field route_id: missing");

        let mut v = good();
        v["status"] = json!(1);
        assert_eq!(reason_of(&v), "field status: expected a string, got number");

        let mut v = good();
        v["infractions"] = json!([]);
        assert_eq!(
            reason_of(&v),
            "field infractions: expected an object, got array"
        );

        let mut v = good();
        v["infractions"]["red_light"] = json!("x");
        assert_eq!(
            reason_of(&v),
            "field infractions.red_light: expected an array of strings, got string"
        );

        let mut v = good();
        v["infractions"]["red_light"] = json!(["a", 3]);
        assert_eq!(
            reason_of(&v),
            "field infractions.red_light[1]: expected a string, got number"
        );

        let mut v = good();
        v["meta"]["route_length"] = json!("far");
        assert_eq!(
            reason_of(&v),
            "field meta.route_length: expected a number, got string"
        );

        assert_eq!(
            reason_of(&json!(3)),
            "record: expected an object, got number"
        );
    }

    #[test]
    fn success_rule() {
        let mut v = good();
        v["status"] = json!("Perfect");
        assert!(Record::from_value(&v).unwrap().is_success());
        v["status"] = json!("Failed - TickRuntime");
        assert!(!Record::from_value(&v).unwrap().is_success());
        let mut v = good();
        v["infractions"]["route_timeout"] = json!(["Route timeout."]);
        assert!(!Record::from_value(&v).unwrap().is_success());
        // an unknown extra list also breaks a success
        let mut v = good();
        v["infractions"]["collisions_ufo"] = json!(["x"]);
        let r = Record::from_value(&v).unwrap();
        assert!(!r.is_success());
        let unknown: Vec<_> = r.infractions.unknown().collect();
        assert_eq!(unknown, vec![("collisions_ufo", &["x".to_string()][..])]);
    }

    #[test]
    fn infractions_keep_unknown_order() {
        let inf = Infractions::from_lists([
            ("zeta", vec!["1".to_string()]),
            ("red_light", vec!["r".to_string()]),
            ("alpha", vec![]),
        ]);
        let names: Vec<_> = inf.unknown().map(|(n, _)| n).collect();
        assert_eq!(names, ["zeta", "alpha"]);
        assert_eq!(inf.list("red_light"), ["r".to_string()]);
        assert_eq!(inf.list("zeta"), ["1".to_string()]);
        assert_eq!(inf.all().count(), 14);
        assert!(!inf.clean_except_min_speed());
    }

    #[test]
    fn ids_and_types() {
        let mut r = Record::from_value(&good()).unwrap();
        r.route_id = "Route_7".into();
        assert_eq!(r.xml_id(), None);
        r.route_id = "RouteScenario_12_repx".into();
        assert_eq!(r.xml_id(), None);
        r.scenario_name = "Accident".into();
        assert_eq!(r.scenario_type(), "Accident");
        r.scenario_name = "Parking_Cut_In_2".into();
        assert_eq!(r.scenario_type(), "Parking_Cut_In");
    }
}
