//! `sds.long_tables` / `sds.to_pandas` (docs/TABLES-SCHEMA.md): the library's own long-table builder
//! ([`monitor_host::report::long_tables::report_node_tables`], the rows and columns of
//! `sds score --tables`' `routes.csv` and `events.csv`) over a report's JSON text, returned as
//! typed columns: no table rule is written again in Python.

use monitor_host::report::long_tables::{report_node_tables, Node, NodeTable};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::errors::InputError;

/// A leaf as a Python value: `None`, `bool`, `int`, `float`, `str`; a list (or an object) as
/// its JSON text, as the CSV cell holds it.
fn leaf<'py>(py: Python<'py>, n: &Node) -> PyResult<Bound<'py, PyAny>> {
    Ok(match n {
        Node::Null => py.None().into_bound(py),
        Node::Bool(b) => b.into_pyobject(py)?.to_owned().into_any(),
        Node::Number(x) => match (x.as_u64(), x.as_i64(), x.as_f64()) {
            (Some(u), _, _) => u.into_pyobject(py)?.into_any(),
            (None, Some(i), _) => i.into_pyobject(py)?.into_any(),
            (None, None, Some(f)) => f.into_pyobject(py)?.into_any(),
            (None, None, None) => py.None().into_bound(py),
        },
        Node::String(s) => s.into_pyobject(py)?.into_any(),
        Node::Array(_) | Node::Object(_) => n.json_text().into_pyobject(py)?.into_any(),
    })
}

/// A table as `(columns, {column: values})`, the values in row order.
fn columns<'py>(py: Python<'py>, t: &NodeTable) -> PyResult<Bound<'py, PyAny>> {
    let data = PyDict::new(py);
    for (c, name) in t.columns.iter().enumerate() {
        let values = PyList::empty(py);
        for row in &t.rows {
            values.append(leaf(py, row.get(c).unwrap_or(&Node::Null))?)?;
        }
        data.set_item(name, values)?;
    }
    (t.columns.clone(), data)
        .into_pyobject(py)
        .map(|t| t.into_any())
}

/// The `routes` and `events` tables of the JSON report `report_json` (the text of
/// `sds score --format json`, or `json.dumps` of `sds.score`'s dict): a dict from table name
/// to `(columns, {column: values})`. Raises `InputError` for text that is not JSON.
#[pyfunction]
pub fn long_tables<'py>(py: Python<'py>, report_json: &str) -> PyResult<Bound<'py, PyAny>> {
    let tree: Node = serde_json::from_str(report_json)
        .map_err(|e| InputError::new_err(format!("the report is not JSON: {e}")))?;
    let (routes, events) = py.detach(|| report_node_tables(&tree));
    let out = PyDict::new(py);
    out.set_item("routes", columns(py, &routes)?)?;
    out.set_item("events", columns(py, &events)?)?;
    Ok(out.into_any())
}
