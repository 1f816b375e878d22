//! Long tables (docs/TABLES-SCHEMA.md), for DataFrames, DuckDB and Spark: `routes` (one row
//! per route row of the report), `events` (one row per entry of a route's `events[]`) and
//! `frames` (one row per frame of a route with telemetry: its `time`, then the values `sds
//! frames` prints), as CSV. `docs/TABLES-SCHEMA.md` names every column, its type and unit.
//!
//! The columns come from the JSON report's own value tree (the JSON text read back, its key
//! order kept): every scalar of the per-route object, nested objects joined with `.`
//! (`comfort.failed.lon_acc`), lists as JSON text. A field added to the report appears here by
//! itself, and a cell holds the very number the JSON prints: the JSON's shortest round-trip
//! decimal read back as an f64 is printed by the same formatter as the JSON writer (serde_json's own, through
//! [`serde_json::Number`]). A column that a row lacks is an empty cell, and so is `null`.
//! Column order is the JSON's field order (a field only some rows have sits after the field it
//! follows in those rows). String cells go through [`csv_cell`], as every CSV of the tool.

use std::collections::{HashMap, HashSet};
use std::fmt;

use serde::de::{Deserialize, Deserializer, MapAccess, SeqAccess, Visitor};

use crate::input::duplicates::Source;
use crate::model::frames::RouteFrames;
use crate::model::report::Report;
use crate::report::escape::{csv_cell, is_hidden};

/// The file names `--tables DIR` writes.
pub const TABLE_NAMES: [&str; 3] = ["routes.csv", "events.csv", "frames.csv"];

/// The file `sds compare --sweep --tables DIR` writes beside `routes.csv` and `events.csv`.
pub const SWEEP_TABLE: &str = "sweep.csv";

/// A JSON value with its object keys in the order of the text (serde_json's own `Value` sorts
/// them unless its `preserve_order` feature is on, which would change other outputs).
#[derive(Clone, Debug, PartialEq)]
pub enum Node {
    /// `null`.
    Null,
    /// `true` / `false`.
    Bool(bool),
    /// A number, printed as serde_json prints it.
    Number(serde_json::Number),
    /// A string.
    String(String),
    /// A list (a table cell holds it as JSON text).
    Array(Vec<Node>),
    /// An object, keys in text order.
    Object(Vec<(String, Node)>),
}

impl<'de> Deserialize<'de> for Node {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Node, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = Node;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("a JSON value")
            }
            fn visit_unit<E>(self) -> Result<Node, E> {
                Ok(Node::Null)
            }
            fn visit_none<E>(self) -> Result<Node, E> {
                Ok(Node::Null)
            }
            fn visit_bool<E>(self, b: bool) -> Result<Node, E> {
                Ok(Node::Bool(b))
            }
            fn visit_u64<E>(self, n: u64) -> Result<Node, E> {
                Ok(Node::Number(n.into()))
            }
            fn visit_i64<E>(self, n: i64) -> Result<Node, E> {
                Ok(Node::Number(n.into()))
            }
            fn visit_f64<E>(self, x: f64) -> Result<Node, E> {
                Ok(serde_json::Number::from_f64(x).map_or(Node::Null, Node::Number))
            }
            fn visit_str<E>(self, s: &str) -> Result<Node, E> {
                Ok(Node::String(s.to_string()))
            }
            fn visit_string<E>(self, s: String) -> Result<Node, E> {
                Ok(Node::String(s))
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut a: A) -> Result<Node, A::Error> {
                let mut v = Vec::new();
                while let Some(n) = a.next_element()? {
                    v.push(n);
                }
                Ok(Node::Array(v))
            }
            fn visit_map<A: MapAccess<'de>>(self, mut a: A) -> Result<Node, A::Error> {
                let mut v = Vec::new();
                while let Some((k, n)) = a.next_entry()? {
                    v.push((k, n));
                }
                Ok(Node::Object(v))
            }
        }
        d.deserialize_any(V)
    }
}

impl Node {
    /// The value at `key` of an object (`None` for anything else or a missing key).
    pub fn get(&self, key: &str) -> Option<&Node> {
        match self {
            Node::Object(kv) => kv.iter().find(|(k, _)| k == key).map(|(_, v)| v),
            _ => None,
        }
    }

    /// The JSON text of the value, with every character [`is_hidden`] holds written as a
    /// `\uXXXX` escape, so the text stays valid JSON and [`csv_cell`] leaves it unchanged.
    pub fn json_text(&self) -> String {
        let mut out = String::new();
        self.write_json(&mut out);
        out
    }

    fn write_json(&self, out: &mut String) {
        match self {
            Node::Null => out.push_str("null"),
            Node::Bool(b) => out.push_str(if *b { "true" } else { "false" }),
            Node::Number(n) => out.push_str(&n.to_string()),
            Node::String(s) => json_string(s, out),
            Node::Array(v) => {
                out.push('[');
                for (i, n) in v.iter().enumerate() {
                    if i > 0 {
                        out.push(',');
                    }
                    n.write_json(out);
                }
                out.push(']');
            }
            Node::Object(kv) => {
                out.push('{');
                for (i, (k, n)) in kv.iter().enumerate() {
                    if i > 0 {
                        out.push(',');
                    }
                    json_string(k, out);
                    out.push(':');
                    n.write_json(out);
                }
                out.push('}');
            }
        }
    }

    /// The CSV cell of a leaf: empty for `null`, numbers as the JSON prints them, strings and
    /// lists (as JSON text) through [`csv_cell`].
    pub fn cell(&self) -> String {
        match self {
            Node::Null => String::new(),
            Node::Bool(b) => b.to_string(),
            Node::Number(n) => n.to_string(),
            Node::String(s) => csv_cell(s).into_owned(),
            Node::Array(_) | Node::Object(_) => csv_cell(&self.json_text()).into_owned(),
        }
    }
}

fn json_string(s: &str, out: &mut String) {
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if is_hidden(c) => out.push_str(&format!("\\u{:04x}", c as u32)),
            c => out.push(c),
        }
    }
    out.push('"');
}

/// The leaves of an object, their names joined with `.`; a list is one leaf.
fn flatten<'a>(prefix: &str, node: &'a Node, out: &mut Vec<(String, &'a Node)>) {
    match node {
        Node::Object(kv) => {
            for (k, v) in kv {
                let name = if prefix.is_empty() {
                    k.clone()
                } else {
                    format!("{prefix}.{k}")
                };
                flatten(&name, v, out);
            }
        }
        leaf => out.push((prefix.to_string(), leaf)),
    }
}

/// A row's leaf names, each with whether it holds something other than `null`.
fn shape_of(leaves: &[(String, &Node)]) -> Vec<(String, bool)> {
    leaves
        .iter()
        .map(|(k, v)| (k.clone(), !matches!(v, Node::Null)))
        .collect()
}

/// The columns of a table, built from the rows' shapes in two passes ([`Columns::add`] for
/// every row, then [`Columns::finish`]).
#[derive(Default)]
struct Columns {
    names: Vec<String>,
    /// Whether a column ever holds something other than `null`.
    filled: HashMap<String, bool>,
    shapes: HashSet<Vec<(String, bool)>>,
}

impl Columns {
    /// Takes a row's leaf names: a name not seen yet goes right after the name before it in
    /// this row (the JSON's field order).
    fn add(&mut self, leaves: &[(String, &Node)]) {
        self.add_shape(shape_of(leaves));
    }

    /// [`Columns::add`] for a row's shape ([`shape_of`]).
    fn add_shape(&mut self, shape: Vec<(String, bool)>) {
        if self.shapes.contains(&shape) {
            return;
        }
        let mut at = 0;
        for (k, filled) in &shape {
            match self.names.iter().position(|n| n == k) {
                Some(i) => at = i + 1,
                None => {
                    self.names.insert(at, k.clone());
                    at += 1;
                }
            }
            *self.filled.entry(k.clone()).or_default() |= *filled;
        }
        self.shapes.insert(shape);
    }

    /// The columns: a name that is always `null` where other rows have an object under it
    /// (`decomposition` next to `decomposition.rounding`) is left out: its rows are the empty
    /// cells of the object's columns.
    fn finish(self) -> Vec<String> {
        let names = &self.names;
        names
            .iter()
            .filter(|n| {
                self.filled.get(*n).copied().unwrap_or(false)
                    || !names.iter().any(|m| {
                        m.len() > n.len()
                            && m.starts_with(n.as_str())
                            && m.as_bytes()[n.len()] == b'.'
                    })
            })
            .cloned()
            .collect()
    }
}

/// A table: its header and its rows of cells (already CSV cell text).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Table {
    /// The column names.
    pub columns: Vec<String>,
    /// The rows, each as long as `columns`.
    pub rows: Vec<Vec<String>>,
    /// More rows, already written as CSV (after `rows`): the frames, written route by route.
    pub body: Vec<u8>,
}

impl Table {
    /// The table as RFC 4180 CSV (the `csv` crate's quoting), a header line first.
    ///
    /// # Errors
    /// Only if the CSV writer fails, which writing to memory rules out.
    pub fn csv(&self) -> Result<Vec<u8>, String> {
        let mut w = ::csv::Writer::from_writer(Vec::new());
        let err = |e: ::csv::Error| e.to_string();
        w.write_record(&self.columns).map_err(err)?;
        for r in &self.rows {
            w.write_record(r).map_err(err)?;
        }
        let mut out = w.into_inner().map_err(|e| e.to_string())?;
        out.extend_from_slice(&self.body);
        Ok(out)
    }
}

/// A table of values (the JSON's leaves; `Node::Null` for an empty cell): its column names and
/// its rows, each as long as the columns. What [`Table`] writes as CSV cells, for front ends
/// that want typed columns (the Python binding's DataFrames and Parquet).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct NodeTable {
    /// The column names.
    pub columns: Vec<String>,
    /// The rows: key cells first (indices as numbers, ids as strings), then the fields.
    pub rows: Vec<Vec<Node>>,
}

/// Builds a table from rows given as key cells (the same names for every row, first) and an
/// object whose leaves are the rest.
fn node_table(keys: &[&str], rows: &[(Vec<Node>, &Node)]) -> NodeTable {
    let mut columns = Columns::default();
    let mut leaves = Vec::with_capacity(rows.len());
    for (_, node) in rows {
        let mut l = Vec::new();
        flatten("", node, &mut l);
        columns.add(&l);
        leaves.push(l);
    }
    let names = columns.finish();
    let position: HashMap<&str, usize> = names
        .iter()
        .enumerate()
        .map(|(i, n)| (n.as_str(), i))
        .collect();
    let rows = rows
        .iter()
        .zip(leaves)
        .map(|((key, _), l)| {
            let mut cells = vec![Node::Null; names.len()];
            for (k, v) in l {
                if let Some(&i) = position.get(k.as_str()) {
                    cells[i] = v.clone();
                }
            }
            key.iter().cloned().chain(cells).collect()
        })
        .collect();
    NodeTable {
        columns: keys.iter().map(|k| k.to_string()).chain(names).collect(),
        rows,
    }
}

/// [`node_table`] as CSV cells.
fn table(keys: &[&str], rows: &[(Vec<Node>, &Node)]) -> Table {
    let t = node_table(keys, rows);
    Table {
        columns: t.columns,
        rows: t
            .rows
            .iter()
            .map(|r| r.iter().map(Node::cell).collect())
            .collect(),
        body: Vec::new(),
    }
}

/// The report's value tree: its JSON text read back, key order kept.
///
/// # Errors
/// Only if the report cannot be serialised, which its types rule out.
pub fn report_tree(report: &Report) -> Result<Node, String> {
    let json = crate::report::json::json(report).map_err(|e| e.to_string())?;
    serde_json::from_slice(&json).map_err(|e| e.to_string())
}

/// The `routes` and `events` tables of a report tree ([`report_tree`]), each row led by
/// `extra` key cells (`sds compare`'s `run` and `model`; none for `sds score`).
fn routes_and_events(
    tree: &Node,
    extra: &[(&str, &str)],
    routes: &mut Vec<(Vec<Node>, Node)>,
    events: &mut Vec<(Vec<Node>, Node)>,
) {
    let Some(Node::Array(rows)) = tree.get("routes") else {
        return;
    };
    for (i, r) in rows.iter().enumerate() {
        let mut key: Vec<Node> = extra
            .iter()
            .map(|(_, v)| Node::String(v.to_string()))
            .collect();
        key.push(Node::Number(i.into()));
        routes.push((key.clone(), r.clone()));
        let id = match r.get("route_id") {
            Some(Node::String(s)) => s.clone(),
            _ => String::new(),
        };
        if let Some(Node::Array(es)) = r.get("events") {
            for (j, e) in es.iter().enumerate() {
                let mut k = key.clone();
                k.push(Node::String(id.clone()));
                k.push(Node::Number(j.into()));
                events.push((k, e.clone()));
            }
        }
    }
}

/// The `routes` and `events` tables of a report's value tree ([`report_tree`], or the JSON
/// report of `sds score` read back as a [`Node`]) as values, the very rows and columns of
/// `routes.csv` and `events.csv` before they become CSV cells.
///
/// ```
/// use monitor_host::report::long_tables::{report_node_tables, Node};
/// let tree: Node = serde_json::from_str(
///     r#"{"routes": [{"route_id": "R1", "comfort": {"score": 1.0}, "events": [{"kind": "stationary"}]}]}"#,
/// ).unwrap();
/// let (routes, events) = report_node_tables(&tree);
/// assert_eq!(routes.columns, ["route_index", "route_id", "comfort.score", "events"]);
/// assert_eq!(events.columns, ["route_index", "route_id", "event_index", "kind"]);
/// assert_eq!(routes.rows[0][2].cell(), "1.0");
/// ```
pub fn report_node_tables(tree: &Node) -> (NodeTable, NodeTable) {
    let (mut routes, mut events) = (Vec::new(), Vec::new());
    routes_and_events(tree, &[], &mut routes, &mut events);
    (
        node_table(&["route_index"], &borrow(&routes)),
        node_table(
            &["route_index", "route_id", "event_index"],
            &borrow(&events),
        ),
    )
}

/// The long tables of one scored run (`sds score`) or of the runs of a comparison
/// (`sds compare`: `run` and `model` columns first, no `frames`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LongTables {
    /// One row per route row of the report: `route_index` (its position in the report's
    /// `routes`), then every field.
    pub routes: Table,
    /// One row per event: `route_index`, `route_id`, `event_index`, then every field.
    pub events: Table,
    /// One row per frame of each route with telemetry: `route_index`, `route_id`, `frame`
    /// (0-based, the `frame` of the events), `time` (s from the route's first frame), then the
    /// fields of `sds frames`; `None` for a comparison.
    pub frames: Option<Table>,
    /// With `sds compare --sweep`: one row per point and model ([`sweep_table`]).
    pub sweep: Option<Table>,
}

impl LongTables {
    /// The files `--tables DIR` writes: `routes.csv`, `events.csv`, and `frames.csv` when
    /// there are frames to write (`sds score`).
    ///
    /// # Errors
    /// As [`Table::csv`].
    pub fn files(&self) -> Result<Vec<(&'static str, Vec<u8>)>, String> {
        let mut files = vec![
            (TABLE_NAMES[0], self.routes.csv()?),
            (TABLE_NAMES[1], self.events.csv()?),
        ];
        if let Some(f) = &self.frames {
            files.push((TABLE_NAMES[2], f.csv()?));
        }
        if let Some(t) = &self.sweep {
            files.push((SWEEP_TABLE, t.csv()?));
        }
        Ok(files)
    }
}

/// The `routes` and `events` tables of the runs of a comparison: each run's report (as
/// `sds score` of that run writes it) under its `run` and `model` names.
///
/// # Errors
/// As [`report_tree`].
///
/// ```
/// use monitor_host::{demo, report::long_tables::compare_tables, score_run, Inputs, Settings};
/// let dir = std::env::temp_dir().join(format!("sds-ctables-doc-{}", std::process::id()));
/// let run = demo::write(&dir).unwrap();
/// let report = score_run(&Inputs::new([run.results.clone()]), &Settings::default()).unwrap();
/// let t = compare_tables(&[("a", "a", &report), ("b", "b", &report)]).unwrap();
/// assert_eq!(&t.routes.columns[..3], ["run", "model", "route_index"]);
/// assert_eq!(t.routes.rows.len(), 2 * report.routes.len());
/// assert!(t.frames.is_none());
/// # std::fs::remove_dir_all(&dir).unwrap();
/// ```
pub fn compare_tables(runs: &[(&str, &str, &Report)]) -> Result<LongTables, String> {
    let (mut routes, mut events) = (Vec::new(), Vec::new());
    for (run, model, report) in runs {
        let tree = report_tree(report)?;
        routes_and_events(
            &tree,
            &[("run", run), ("model", model)],
            &mut routes,
            &mut events,
        );
    }
    Ok(LongTables {
        routes: table(&["run", "model", "route_index"], &borrow(&routes)),
        events: table(
            &["run", "model", "route_index", "route_id", "event_index"],
            &borrow(&events),
        ),
        frames: None,
        sweep: None,
    })
}

/// The `sweep` table of `sds compare --sweep` (docs/SCORE.md §10.4): one row per point and model, `point`
/// (its index in the report's `sweep.points`), each swept setting's value (a column named after
/// the setting), then `model`, `ds_safe`, `comfort`, `sds`, `rank`; the cells are the JSON's.
///
/// ```
/// use monitor_host::report::long_tables::sweep_table;
/// use monitor_host::settings::defs::Value;
/// use monitor_host::stats::sweep::report;
/// let at = vec![("critical_excess".to_string(), Value::F32(0.5))];
/// let s = report(&["critical_excess".into()], &["a".into(), "b".into()],
///     vec![(at, vec![[Some(60.0), Some(0.9), Some(54.0)], [None, None, None]])]);
/// let t = sweep_table(&s);
/// assert_eq!(t.columns, ["point", "critical_excess", "model", "ds_safe", "comfort", "sds", "rank"]);
/// assert_eq!(t.rows[0], ["0", "0.5", "a", "60.0", "0.9", "54.0", "1"]);
/// assert_eq!(t.rows[1][3..], ["", "", "", ""]);
/// ```
pub fn sweep_table(s: &crate::stats::sweep::SweepReport) -> Table {
    let number = |x: Option<f64>| {
        x.and_then(serde_json::Number::from_f64)
            .map_or_else(String::new, |n| n.to_string())
    };
    let value = |v: &crate::settings::defs::Value| match serde_json::to_value(v) {
        Ok(serde_json::Value::String(t)) => csv_cell(&t).into_owned(),
        Ok(serde_json::Value::Null) | Err(_) => String::new(),
        Ok(other) => csv_cell(&other.to_string()).into_owned(),
    };
    let columns: Vec<String> = ["point"]
        .into_iter()
        .map(String::from)
        .chain(s.settings.iter().cloned())
        .chain(
            ["model", "ds_safe", "comfort", "sds", "rank"]
                .into_iter()
                .map(String::from),
        )
        .collect();
    let mut rows = Vec::new();
    for (i, p) in s.points.iter().enumerate() {
        for m in &p.models {
            rows.push(
                std::iter::once(i.to_string())
                    .chain(p.values.iter().map(|(_, v)| value(v)))
                    .chain([
                        csv_cell(&m.model).into_owned(),
                        number(m.ds_safe),
                        number(m.comfort),
                        number(m.sds),
                        m.rank.map_or_else(String::new, |r| r.to_string()),
                    ])
                    .collect(),
            );
        }
    }
    Table {
        columns,
        rows,
        body: Vec::new(),
    }
}

/// The long tables of a run: `report` and the frames of its routes ([`crate::run_frames`],
/// matched to the report's rows by their `source`; a row without frames has no `frames` rows).
///
/// # Errors
/// A frame the core's encoder cannot write, named by route and step.
///
/// ```
/// use monitor_host::{demo, report::long_tables::long_tables, run_frames, score_run, Inputs, Settings};
/// let dir = std::env::temp_dir().join(format!("sds-tables-doc-{}", std::process::id()));
/// let run = demo::write(&dir).unwrap();
/// let inputs = Inputs { telemetry: Some(run.telemetry.clone()), ..Inputs::new([run.results.clone()]) };
/// let settings = Settings::default();
/// let report = score_run(&inputs, &settings).unwrap();
/// let frames: Vec<_> = run_frames(&inputs, &settings).unwrap().into_iter()
///     .filter_map(|(s, f)| Some((s, f.ok()?))).collect();
/// let t = long_tables(&report, &frames).unwrap();
/// assert_eq!(t.routes.rows.len(), report.routes.len());
/// assert_eq!(&t.routes.columns[..2], ["route_index", "route_id"]);
/// assert!(t.frames.unwrap().columns.contains(&"host.step".to_string()));
/// # std::fs::remove_dir_all(&dir).unwrap();
/// ```
pub fn long_tables(
    report: &Report,
    frames: &[(Source, RouteFrames)],
) -> Result<LongTables, String> {
    let tree = report_tree(report)?;
    let (mut routes, mut events) = (Vec::new(), Vec::new());
    routes_and_events(&tree, &[], &mut routes, &mut events);
    let framed: Vec<(usize, String, &RouteFrames)> = report
        .routes
        .iter()
        .enumerate()
        .filter_map(|(i, r)| {
            let source = r.source.as_ref()?;
            let (_, f) = frames.iter().find(|(s, _)| s == source)?;
            Some((i, r.route_id.clone().unwrap_or_default(), f))
        })
        .collect();
    let frames = frames_table(&framed)?;
    Ok(LongTables {
        routes: table(&["route_index"], &borrow(&routes)),
        events: table(
            &["route_index", "route_id", "event_index"],
            &borrow(&events),
        ),
        frames: Some(frames),
        sweep: None,
    })
}

/// A line of `sds frames` split for the frames table: its skeleton (the text with every number
/// written as `#`: two lines of one skeleton have the same leaves, names and nulls) and its
/// leaf values' byte ranges in text order (the order of [`flatten`]). `None` for a line with a
/// list (a list is one leaf; such a line takes the slow path).
fn split_line(line: &[u8], skeleton: &mut Vec<u8>, values: &mut Vec<(usize, usize)>) -> Option<()> {
    skeleton.clear();
    values.clear();
    let mut i = 0;
    while i < line.len() {
        match line[i] {
            b'[' | b']' => return None,
            b'"' => {
                let start = i;
                i += 1;
                while i < line.len() && line[i] != b'"' {
                    i += if line[i] == b'\\' { 2 } else { 1 };
                }
                i = (i + 1).min(line.len());
                skeleton.extend_from_slice(&line[start..i]);
                let next = line[i..].iter().find(|b| !b.is_ascii_whitespace());
                if next != Some(&b':') {
                    values.push((start, i));
                }
            }
            b'-' | b'0'..=b'9' => {
                let start = i;
                while i < line.len()
                    && matches!(line[i], b'-' | b'+' | b'.' | b'e' | b'E' | b'0'..=b'9')
                {
                    i += 1;
                }
                skeleton.push(b'#');
                values.push((start, i));
            }
            b't' | b'f' | b'n' => {
                let start = i;
                while i < line.len() && line[i].is_ascii_alphabetic() {
                    i += 1;
                }
                skeleton.extend_from_slice(&line[start..i]);
                values.push((start, i));
            }
            b => {
                skeleton.push(b);
                i += 1;
            }
        }
    }
    Some(())
}

/// The CSV cell of one leaf's JSON text, as [`Node::cell`] writes that leaf.
fn value_cell(text: &[u8]) -> Result<String, String> {
    match text {
        b"null" => Ok(String::new()),
        b"true" | b"false" => Ok(String::from_utf8_lossy(text).into_owned()),
        _ => serde_json::from_slice::<Node>(text)
            .map(|n| n.cell())
            .map_err(|e| e.to_string()),
    }
}

/// Each frame of `route` (its index, id and frames) as its `sds frames` line: `each` gets the
/// frame index, the line's skeleton and leaf ranges ([`split_line`]; `None` for a line with a
/// list) and the line.
fn each_line(
    (_, id, f): &(usize, String, &RouteFrames),
    mut each: impl FnMut(usize, Option<(&[u8], &[(usize, usize)])>, &[u8]) -> Result<(), String>,
) -> Result<(), String> {
    let lines = crate::report::frames::frame_lines(f).map_err(|e| format!("{id}: {e}"))?;
    let (mut skeleton, mut values) = (Vec::new(), Vec::new());
    let lines = lines.split(|&b| b == b'\n').filter(|l| !l.is_empty());
    for (k, line) in lines.enumerate() {
        let split = split_line(line, &mut skeleton, &mut values);
        each(k, split.map(|()| (&skeleton[..], &values[..])), line)?;
    }
    Ok(())
}

/// A line's leaves read back through [`Node`] (the slow path, once per skeleton).
fn line_leaves(id: &str, line: &[u8]) -> Result<Node, String> {
    serde_json::from_slice(line).map_err(|e| format!("{id}: {e}"))
}

/// The `frames` table, built route by route in two passes (the columns, then the rows as CSV),
/// so that a benchmark-sized run never holds its frames' values all at once. Each line is read
/// back through [`Node`] once per skeleton ([`split_line`]: the lines of a route share a few);
/// the other lines' leaves are cut out of the text by position and written by [`value_cell`],
/// the very cells the slow path writes (880,000 frames: 16.9 s before, see PERFORMANCE.md).
fn frames_table(framed: &[(usize, String, &RouteFrames)]) -> Result<Table, String> {
    use rayon::prelude::*;
    // A run without frames (no telemetry) still gets the columns every frame line has, so that
    // a query naming them (DuckDB, pandas) reads an empty table rather than failing to bind.
    let blank = RouteFrames {
        frames: vec![monitor_core::Frame::default()],
        steps: vec![0],
        lateral: vec![None],
        reference: crate::geometry::corridor::ReferenceKind::None,
        dt: 0.05,
        warnings: Vec::new(),
        files_read: Vec::new(),
    };
    let header_only = [(0, String::new(), &blank)];
    let shaped = if framed.is_empty() {
        &header_only[..]
    } else {
        framed
    };
    // Pass 1: each route's distinct shapes in order, merged in route order.
    let shapes: Vec<Vec<Vec<(String, bool)>>> = shaped
        .par_iter()
        .map(|route| {
            let (mut seen, mut shapes) = (HashSet::new(), Vec::new());
            let mut skeletons: HashSet<Vec<u8>> = HashSet::new();
            each_line(route, |_, split, line| {
                if let Some((skeleton, _)) = split {
                    if skeletons.contains(skeleton) {
                        return Ok(());
                    }
                    skeletons.insert(skeleton.to_vec());
                }
                let node = line_leaves(&route.1, line)?;
                let mut l = Vec::new();
                flatten("", &node, &mut l);
                let shape = shape_of(&l);
                if seen.insert(shape.clone()) {
                    shapes.push(shape);
                }
                Ok(())
            })?;
            Ok(shapes)
        })
        .collect::<Result<_, String>>()?;
    let mut columns = Columns::default();
    for shape in shapes.into_iter().flatten() {
        columns.add_shape(shape);
    }
    let names = columns.finish();
    let position: HashMap<&str, usize> = names
        .iter()
        .enumerate()
        .map(|(i, n)| (n.as_str(), i))
        .collect();
    // Pass 2: each route's rows as CSV, in route order.
    let bodies: Vec<Vec<u8>> = framed
        .par_iter()
        .map(|route| {
            let mut w = ::csv::Writer::from_writer(Vec::new());
            let (i, id) = (route.0.to_string(), csv_cell(&route.1).into_owned());
            // Per skeleton, each leaf's column (`None`: a name that is no column).
            let mut templates: HashMap<Vec<u8>, Vec<Option<usize>>> = HashMap::new();
            let mut cells = vec![String::new(); names.len()];
            each_line(route, |k, split, line| {
                cells.iter_mut().for_each(String::clear);
                match split {
                    Some((skeleton, values)) => {
                        if !templates.contains_key(skeleton) {
                            let node = line_leaves(&route.1, line)?;
                            let mut l = Vec::new();
                            flatten("", &node, &mut l);
                            let t = l.iter().map(|(c, _)| position.get(c.as_str()).copied());
                            templates.insert(skeleton.to_vec(), t.collect());
                        }
                        let template = &templates[skeleton];
                        if template.len() != values.len() {
                            return Err(format!(
                                "{}: frame {k}: a line the table cannot split",
                                route.1
                            ));
                        }
                        for (p, &(a, b)) in template.iter().zip(values) {
                            if let Some(p) = p {
                                cells[*p] = value_cell(&line[a..b])
                                    .map_err(|e| format!("{}: {e}", route.1))?;
                            }
                        }
                    }
                    None => {
                        let node = line_leaves(&route.1, line)?;
                        let mut l = Vec::new();
                        flatten("", &node, &mut l);
                        for (c, v) in l {
                            if let Some(&p) = position.get(c.as_str()) {
                                cells[p] = v.cell();
                            }
                        }
                    }
                }
                let key = [i.clone(), id.clone(), k.to_string(), time_cell(route.2, k)];
                w.write_record(key.iter().chain(&cells))
                    .map_err(|e| e.to_string())
            })?;
            w.into_inner().map_err(|e| e.to_string())
        })
        .collect::<Result<_, String>>()?;
    Ok(Table {
        columns: ["route_index", "route_id", "frame", "time"]
            .iter()
            .map(|k| k.to_string())
            .chain(names)
            .collect(),
        rows: Vec::new(),
        body: bodies.concat(),
    })
}

/// The `time` cell of frame `k`: seconds from the route's first frame, `(step - first step) ×
/// dt`, the arithmetic of the events' `time_s`, so that an event and its frame agree.
fn time_cell(f: &RouteFrames, k: usize) -> String {
    let (Some(&first), Some(&step)) = (f.steps.first(), f.steps.get(k)) else {
        return String::new();
    };
    let t = step.saturating_sub(first) as f64 * crate::settings::decimal(f.dt);
    serde_json::Number::from_f64(t).map_or_else(String::new, |n| n.to_string())
}

fn borrow(v: &[(Vec<Node>, Node)]) -> Vec<(Vec<Node>, &Node)> {
    v.iter().map(|(k, n)| (k.clone(), n)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The cells the fast path cuts out of a line, against the slow path's (the line read back
    /// through [`Node`] and flattened).
    fn both(line: &str) -> (Vec<String>, Vec<String>) {
        let (mut skeleton, mut values) = (Vec::new(), Vec::new());
        split_line(line.as_bytes(), &mut skeleton, &mut values).unwrap();
        let fast = values
            .iter()
            .map(|&(a, b)| value_cell(&line.as_bytes()[a..b]).unwrap())
            .collect();
        let node: Node = serde_json::from_str(line).unwrap();
        let mut l = Vec::new();
        flatten("", &node, &mut l);
        (fast, l.iter().map(|(_, v)| v.cell()).collect())
    }

    #[test]
    fn i37_split_line_cells_equal_the_tree_cells() {
        for line in [
            r#"{"a_lon":0.49865958,"a_lat":-7.017681e-4,"x":-4.4775767e-5,"n":null,"c":{"p":0,"v":12},"host":{"dt":0.05,"lane_width":null,"reference":"xml","step":1}}"#,
            r#"{"s":"say \"hi\" \\ there","k":1e21,"m":-0.0,"t":true,"f":false,"e":{}}"#,
            r#"{"u":"\u00e9\u200b","z":100.0,"w":1E-7}"#,
        ] {
            let (fast, slow) = both(line);
            assert_eq!(fast, slow, "{line}");
        }
    }

    #[test]
    fn i37_split_line_skeleton_keeps_names_and_nulls() {
        let (mut s1, mut s2, mut v) = (Vec::new(), Vec::new(), Vec::new());
        split_line(br#"{"a":1.5,"b":null,"c":"x"}"#, &mut s1, &mut v).unwrap();
        split_line(br#"{"a":-2,"b":null,"c":"x"}"#, &mut s2, &mut v).unwrap();
        assert_eq!(s1, s2);
        split_line(br#"{"a":-2,"b":3,"c":"x"}"#, &mut s2, &mut v).unwrap();
        assert_ne!(s1, s2, "a null and a number are different shapes");
        assert!(split_line(br#"{"a":[1,2]}"#, &mut s1, &mut v).is_none());
    }
}
