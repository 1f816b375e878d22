//! `sds.Monitor`: the streaming monitor of one route, fed one Bench2Drive `get_metric_info()`
//! dict per tick. Frames are built by the host library's [`LiveFrames`] (the frame builder and
//! lateral corridor `sds score` and `sds frames` use, with the route, the town's map and the
//! lane reference) and pushed through [`monitor_core::Monitor`] (the firmware's code).

use monitor_core::score::{self, RecordScores};
use monitor_core::{Collisions, Event, Events, Frame, MonitorError};
use std::path::PathBuf;
use std::sync::Arc;

use monitor_host::error::message;
use monitor_host::input::collision::{is_workzone, CollisionList};
use monitor_host::input::telemetry::{FieldProblem, TelemetryError, TelemetryFrame};
use monitor_host::pipeline::live::{load_map, LiveFrames, Tick};
use monitor_host::Settings;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};

use crate::convert::serialize;
use crate::errors::{live_error, settings_error, ConfigError, InputError, SdsError};
use crate::options::setting_pairs;

/// The streaming monitor of one route (see the Python class `sds.Monitor`).
#[pyclass(module = "sds._sds", subclass)]
pub struct Monitor {
    core: monitor_core::Monitor,
    /// The frames of the route: signals, speed, and the lateral error against the route or
    /// lane (the library's live frame building).
    builder: LiveFrames<'static>,
    last: Option<Frame>,
    settings: Settings,
}

fn field_error(step: u64, field: &'static str, problem: FieldProblem) -> TelemetryError {
    TelemetryError::Field {
        step,
        field,
        problem,
    }
}

fn number(x: &Bound<'_, PyAny>) -> Option<f64> {
    x.extract::<f64>().ok()
}

/// The first three numbers of a list, tuple, sequence (numpy array) or `carla.Vector3D`-like
/// object (`x`, `y`, `z`).
fn vec3(
    obj: &Bound<'_, PyAny>,
    step: u64,
    field: &'static str,
) -> Result<[f64; 3], TelemetryError> {
    let err = |p| field_error(step, field, p);
    let mut out = [0.0; 3];
    if let Ok(list) = obj.cast::<PyList>() {
        if list.len() < 3 {
            return Err(err(FieldProblem::TooShort));
        }
        for (i, o) in out.iter_mut().enumerate() {
            let item = list.get_item(i).map_err(|_| err(FieldProblem::TooShort))?;
            *o = number(&item).ok_or(err(FieldProblem::NonNumeric))?;
        }
    } else if let Ok(t) = obj.cast::<PyTuple>() {
        if t.len() < 3 {
            return Err(err(FieldProblem::TooShort));
        }
        for (i, o) in out.iter_mut().enumerate() {
            let item = t.get_item(i).map_err(|_| err(FieldProblem::TooShort))?;
            *o = number(&item).ok_or(err(FieldProblem::NonNumeric))?;
        }
    } else if obj.hasattr("x").unwrap_or(false) && !obj.is_instance_of::<pyo3::types::PyString>() {
        for (o, name) in out.iter_mut().zip(["x", "y", "z"]) {
            let item = obj
                .getattr(name)
                .map_err(|_| err(FieldProblem::NotAnArray))?;
            *o = number(&item).ok_or(err(FieldProblem::NonNumeric))?;
        }
    } else if obj.is_instance_of::<pyo3::types::PyString>() || obj.len().is_err() {
        return Err(err(FieldProblem::NotAnArray));
    } else {
        if obj.len().unwrap_or(0) < 3 {
            return Err(err(FieldProblem::TooShort));
        }
        for (i, o) in out.iter_mut().enumerate() {
            let item = obj.get_item(i).map_err(|_| err(FieldProblem::NotAnArray))?;
            *o = number(&item).ok_or(err(FieldProblem::NonNumeric))?;
        }
    }
    Ok(out)
}

/// A waypoint: `(x, y)`, `(x, y, z)` or an object with `x`, `y` and maybe `z`
/// (`carla.Location`), finite; `z` is 0 when absent (as in a route XML without heights).
fn waypoint(w: &Bound<'_, PyAny>) -> Option<[f64; 3]> {
    let p = if w.hasattr("x").unwrap_or(false) {
        let z = match w.getattr("z") {
            Ok(z) => number(&z)?,
            Err(_) => 0.0,
        };
        [
            number(&w.getattr("x").ok()?)?,
            number(&w.getattr("y").ok()?)?,
            z,
        ]
    } else {
        let z = match w.len() {
            Ok(n) if n >= 3 => number(&w.get_item(2).ok()?)?,
            _ => 0.0,
        };
        [
            number(&w.get_item(0).ok()?)?,
            number(&w.get_item(1).ok()?)?,
            z,
        ]
    };
    p.iter().all(|v| v.is_finite()).then_some(p)
}

/// The five raw vectors of a `get_metric_info()` entry.
fn raw_frame(entry: &Bound<'_, PyAny>, step: u64) -> Result<[[f64; 3]; 5], TelemetryError> {
    let mut raw = [[0.0; 3]; 5];
    let dict = entry.cast::<PyDict>().ok();
    for (slot, name) in raw.iter_mut().zip(TelemetryFrame::FIELDS) {
        let value = match dict {
            Some(d) => d.get_item(name).ok().flatten(),
            None => entry.get_item(name).ok(),
        };
        let value = value.ok_or(field_error(step, name, FieldProblem::Missing))?;
        *slot = vec3(&value, step, name)?;
    }
    Ok(raw)
}

/// A frame's collisions from kind names (`pedestrian`, `vehicle`, `layout`, `workzone`) or CARLA
/// actor blueprint ids (`vehicle.audi.tt`, `static.prop.constructioncone`, ...).
fn collisions_of(kinds: Option<&Bound<'_, PyAny>>, step: u64) -> PyResult<Collisions> {
    let mut c = Collisions::NONE;
    let Some(kinds) = kinds else {
        return Ok(c);
    };
    if kinds.is_instance_of::<pyo3::types::PyString>() {
        return Err(InputError::new_err(format!(
            "step {step}: collisions: expected a sequence of kinds or actor type ids, got a string"
        )));
    }
    for k in kinds.try_iter()? {
        let k: String = k?.extract()?;
        let (list, workzone) = match k.as_str() {
            "pedestrian" => (CollisionList::Pedestrian, false),
            "vehicle" => (CollisionList::Vehicle, false),
            "layout" => (CollisionList::Layout, false),
            "workzone" => (CollisionList::Layout, true),
            id => match CollisionList::of_actor(id) {
                Some(list) => (list, list == CollisionList::Layout && is_workzone(id)),
                None => {
                    return Err(InputError::new_err(format!(
                        "step {step}: collision {id:?}: not a kind (pedestrian, vehicle, layout, \
                         workzone) nor the type id of an actor the leaderboard counts"
                    )))
                }
            },
        };
        list.count_in(workzone, &mut c);
    }
    Ok(c)
}

fn monitor_error(step: u64, e: MonitorError) -> PyErr {
    match e {
        MonitorError::Finished => SdsError::new_err(format!(
            "step {step}: {e} (start a new Monitor for the next route)"
        )),
        _ => InputError::new_err(format!("step {step}: {e}")),
    }
}

/// One event as a dict: `kind` (`collision`, `comfort`, `lateral`) and the verdict's fields,
/// plus `nodecel` (collision) or `comfortable` (comfort).
fn event_dict<'py>(py: Python<'py>, e: &Event) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let (kind, body) = match e {
        Event::Collision(v) => ("collision", serialize(py, v)?),
        Event::Comfort(v) => ("comfort", serialize(py, v)?),
        Event::Lateral(v) => ("lateral", serialize(py, v)?),
    };
    d.set_item("kind", kind)?;
    d.update(body.cast::<PyDict>()?.as_mapping())?;
    match e {
        Event::Collision(v) => d.set_item("nodecel", v.nodecel())?,
        Event::Comfort(v) => d.set_item("comfortable", v.failed.comfortable())?,
        Event::Lateral(_) => {}
    }
    Ok(d)
}

fn append_events(py: Python<'_>, out: &Bound<'_, PyList>, events: &Events) -> PyResult<()> {
    for e in events {
        out.append(event_dict(py, e)?)?;
    }
    Ok(())
}

impl Monitor {
    /// The step of the next frame: `step`, or the previous step + 1 (0 for the first frame).
    fn next_step(&self, step: Option<u64>) -> u64 {
        self.builder.next_step(step)
    }

    /// Builds and pushes one frame; nothing changes when the frame is refused.
    fn push_frame(
        &mut self,
        step: Option<u64>,
        raw: impl FnOnce(u64) -> Result<[[f64; 3]; 5], TelemetryError>,
        collisions: Collisions,
        lat_err: Option<f64>,
    ) -> PyResult<Events> {
        let step = self.next_step(step);
        let tick = raw(step)
            .map(Tick::from_raw)
            .map_err(|e| InputError::new_err(message(&e)))?;
        let checkpoint = self.builder.checkpoint();
        let frame = self
            .builder
            .push(Some(step), &tick, collisions, lat_err)
            .map_err(|e| live_error(&e))?;
        let events = match self.core.push(&frame) {
            Ok(events) => events,
            Err(e) => {
                // Nothing changes for a refused frame: the builder and route search go back.
                self.builder.rewind(checkpoint);
                return Err(monitor_error(step, e));
            }
        };
        self.last = Some(frame);
        Ok(events)
    }
}

#[pymethods]
impl Monitor {
    #[new]
    #[pyo3(signature = (
        profile="physical", dt=0.05, settings=None, *, route=None, maps=None, town=None,
        lateral_reference=None
    ))]
    fn new(
        profile: &str,
        dt: f64,
        settings: Option<&Bound<'_, PyAny>>,
        route: Option<&Bound<'_, PyAny>>,
        maps: Option<PathBuf>,
        town: Option<&str>,
        lateral_reference: Option<&str>,
    ) -> PyResult<Self> {
        let mut s = Settings::default();
        let mut pairs = vec![
            ("profile".to_string(), profile.to_string()),
            ("dt".to_string(), dt.to_string()),
        ];
        if let Some(r) = lateral_reference {
            pairs.push(("lateral_reference".to_string(), r.to_string()));
        }
        pairs.extend(setting_pairs(settings)?);
        s.apply_pairs(pairs).map_err(|e| settings_error(&e))?;
        let core = monitor_core::Monitor::new(s.core)
            .map_err(|e| ConfigError::new_err(format!("invalid configuration: {e}")))?;
        let route = match route {
            None => None,
            Some(r) => {
                let mut waypoints = Vec::new();
                for (i, w) in r.try_iter()?.enumerate() {
                    let p = waypoint(&w?).ok_or_else(|| {
                        InputError::new_err(format!(
                            "route: waypoint {i}: expected (x, y), (x, y, z) or an object with \
                             x and y"
                        ))
                    })?;
                    waypoints.push(p);
                }
                Some(waypoints)
            }
        };
        let map = match maps {
            None => None,
            Some(path) => Some(Arc::new(
                // A town's map takes a while to parse: other Python threads run meanwhile.
                Python::attach(|py| py.detach(|| load_map(&path, town)))
                    .map_err(|e| live_error(&e))?,
            )),
        };
        let builder = LiveFrames::new(route.as_deref(), map, &s).map_err(|e| live_error(&e))?;
        Ok(Monitor {
            core,
            builder,
            last: None,
            settings: s,
        })
    }

    /// Pushes one tick; returns that frame's events.
    #[pyo3(signature = (entry, *, step=None, collisions=None, lat_err=None))]
    fn push<'py>(
        &mut self,
        py: Python<'py>,
        entry: &Bound<'py, PyAny>,
        step: Option<u64>,
        collisions: Option<&Bound<'py, PyAny>>,
        lat_err: Option<f64>,
    ) -> PyResult<Bound<'py, PyList>> {
        let step = self.next_step(step);
        let c = collisions_of(collisions, step)?;
        let events = self.push_frame(Some(step), |s| raw_frame(entry, s), c, lat_err)?;
        let out = PyList::empty(py);
        append_events(py, &out, &events)?;
        Ok(out)
    }

    /// Pushes `n` frames given as native-endian f64 bytes: `data` holds 15 numbers per frame
    /// (the five vectors in `FIELDS` order), `lat_err` one per frame (NaN = unknown).
    #[pyo3(signature = (n, data, steps=None, lat_err=None, collisions=None))]
    fn _push_raw<'py>(
        &mut self,
        py: Python<'py>,
        n: usize,
        data: &[u8],
        steps: Option<Vec<u64>>,
        lat_err: Option<&[u8]>,
        collisions: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyList>> {
        let f64s = |b: &[u8]| -> Vec<f64> {
            b.chunks_exact(8)
                .map(|c| f64::from_ne_bytes(c.try_into().unwrap_or([0; 8])))
                .collect()
        };
        let data = f64s(data);
        let lat = lat_err.map(f64s);
        if data.len() != n * 15
            || lat.as_ref().is_some_and(|l| l.len() != n)
            || steps.as_ref().is_some_and(|s| s.len() != n)
        {
            return Err(InputError::new_err(
                "push_arrays: every array must have one row per frame (vectors: 3 columns)",
            ));
        }
        let out = PyList::empty(py);
        for i in 0..n {
            let step = self.next_step(steps.as_ref().map(|s| s[i]));
            let kinds = match collisions {
                Some(d) => d.get_item(i)?,
                None => None,
            };
            let c = collisions_of(kinds.as_ref(), step)?;
            let mut raw = [[0.0; 3]; 5];
            for (k, v) in raw.iter_mut().enumerate() {
                v.copy_from_slice(&data[i * 15 + k * 3..i * 15 + k * 3 + 3]);
            }
            let l = lat.as_ref().map(|l| l[i]).filter(|x| !x.is_nan());
            let events = self.push_frame(Some(step), |_| Ok(raw), c, l)?;
            append_events(py, &out, &events)?;
        }
        Ok(out)
    }

    /// Ends the route: the last events, the summary and DS_safe.
    #[pyo3(signature = (*, score_route=None, score_penalty=None, workzone=0))]
    fn finish<'py>(
        &mut self,
        py: Python<'py>,
        score_route: Option<f64>,
        score_penalty: Option<f64>,
        workzone: u32,
    ) -> PyResult<Bound<'py, PyDict>> {
        let done = self
            .core
            .finish()
            .map_err(|e| monitor_error(self.builder.last_step().unwrap_or(0), e))?;
        let s = done.summary;
        let d = serialize(py, &s)?.cast_into::<PyDict>()?;
        if let Some(comfort) = d.get_item("comfort")? {
            comfort.set_item("score", s.comfort_score())?;
        }
        let events = PyList::empty(py);
        append_events(py, &events, &done.events)?;
        d.set_item("events", events)?;
        let safe = match (score_route, score_penalty) {
            (Some(score_route), Some(score_penalty)) => Some(score::ds_safe(
                &s,
                &RecordScores {
                    score_route,
                    score_penalty,
                    workzone,
                },
                &self.settings.core.factors,
            )),
            _ => None,
        };
        d.set_item("p_safe", safe.map(|x| x.p_safe))?;
        d.set_item("ds_safe", safe.map(|x| x.ds_safe))?;
        Ok(d)
    }

    /// Frames pushed so far.
    #[getter]
    fn frames(&self) -> u32 {
        self.core.frames()
    }

    /// The step of the last frame pushed, or None.
    #[getter]
    fn last_step(&self) -> Option<u64> {
        self.builder.last_step()
    }

    /// The last frame pushed, as the monitor saw it, or None.
    #[getter]
    fn last_frame<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        self.last.as_ref().map(|f| serialize(py, f)).transpose()
    }

    /// True once `finish` has run.
    #[getter]
    fn finished(&self) -> bool {
        self.core.is_finished()
    }

    /// What the lateral error is measured against: `map-route`, `xml` (the route without a
    /// map), `map-lane` or `none` (the report's `lateral.reference`).
    #[getter]
    fn reference(&self) -> &'static str {
        self.builder.reference().name()
    }

    /// The monitor's configuration (the report's `config` names), as a dict.
    #[getter]
    fn config<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        serialize(py, &self.settings.core)
    }
}
