//! A report's per-route row read back from its JSON (`SDS-SPEC.md` v1.4 §13): the very
//! [`RouteReport`] `sds score` aggregated, so that [`crate::model::report::assemble_rows`]
//! computes a merged report with the code that computed each part. Every field the report
//! writes is read; what it does not write (collision traces, chunk verdicts) stays empty: the
//! parts' traces are referenced, not re-read.

use serde_json::Value;

use crate::geometry::corridor::ReferenceKind;
use crate::input::collision::CollisionList;
use crate::input::duplicates::{DuplicatePolicy, Kept, Source};
use crate::input::warning::Warning;
use crate::pipeline::align::AlignedBy;
use crate::pipeline::outcome::{CollisionEvent, RouteState, TelemetryState};
use crate::pipeline::step_period::DtSource;
use crate::route::ability::{AbilityEntry, JunctionCredit, RouteAbility, ABILITIES};
use crate::route::decomposition::Losses;
use crate::route::events::RouteEvent;
use crate::route::protocol::min_speed::MinSpeedGrid;
use crate::route::protocol::route::{RouteProtocols, RouteScore};
use crate::route::protocol::Protocol;
use crate::route::row::{
    CollisionCounts, ComfortReport, InfractionCounts, LateralReport, PenaltyReport, RouteReport,
};

/// A field of a part that is not what a report writes: its JSON path and what was expected.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{path}: expected {expected}")]
pub struct FieldError {
    /// `routes[3].comfort.score`.
    pub path: String,
    /// `a number or null`.
    pub expected: &'static str,
}

/// The event kinds a report writes (`crate::route::events`).
const EVENT_KINDS: [&str; 15] = [
    "collision",
    "red_light",
    "stop_sign",
    "blocked",
    "route_deviation",
    "outside_lanes",
    "min_speed",
    "yield_emergency_vehicle",
    "scenario_timeout",
    "route_timeout",
    "other",
    "lateral_anomalous",
    "lateral_critical",
    "uncomfortable",
    "stationary",
];

/// How an event is placed, as a report writes it (`log time`: a vehicle log's event, placed by
/// its message's log time).
const PLACED_BY: [&str; 6] = [
    "infractions.json",
    "nearest",
    "closest_approach",
    "motion",
    "chunk",
    "log time",
];

/// A value at a JSON path.
#[derive(Clone, Copy)]
pub(crate) struct At<'a> {
    v: Option<&'a Value>,
    path: &'a str,
    key: &'a str,
}

type R<T> = Result<T, FieldError>;

impl<'a> At<'a> {
    pub(crate) fn new(v: &'a Value, path: &'a str) -> Self {
        At {
            v: Some(v),
            path,
            key: "",
        }
    }

    fn path(&self) -> String {
        if self.key.is_empty() {
            self.path.to_string()
        } else {
            format!("{}.{}", self.path, self.key)
        }
    }

    fn err<T>(&self, expected: &'static str) -> R<T> {
        Err(FieldError {
            path: self.path(),
            expected,
        })
    }

    /// The value, or null when absent.
    fn value(&self) -> &'a Value {
        self.v.unwrap_or(&Value::Null)
    }

    fn is_null(&self) -> bool {
        self.value().is_null()
    }

    fn f64(&self) -> R<f64> {
        self.value()
            .as_f64()
            .map_or_else(|| self.err("a number"), Ok)
    }

    fn opt_f64(&self) -> R<Option<f64>> {
        if self.is_null() {
            return Ok(None);
        }
        self.f64().map(Some)
    }

    fn u64(&self) -> R<u64> {
        self.value()
            .as_u64()
            .map_or_else(|| self.err("a whole number"), Ok)
    }

    fn u32(&self) -> R<u32> {
        u32::try_from(self.u64()?).or_else(|_| self.err("a whole number below 2^32"))
    }

    fn usize(&self) -> R<usize> {
        usize::try_from(self.u64()?).or_else(|_| self.err("a whole number"))
    }

    fn opt_u64(&self) -> R<Option<u64>> {
        if self.is_null() {
            return Ok(None);
        }
        self.u64().map(Some)
    }

    fn opt_usize(&self) -> R<Option<usize>> {
        if self.is_null() {
            return Ok(None);
        }
        self.usize().map(Some)
    }

    fn bool(&self) -> R<bool> {
        self.value()
            .as_bool()
            .map_or_else(|| self.err("true or false"), Ok)
    }

    fn opt_bool(&self) -> R<Option<bool>> {
        if self.is_null() {
            return Ok(None);
        }
        self.bool().map(Some)
    }

    pub(crate) fn str(&self) -> R<&'a str> {
        self.value()
            .as_str()
            .map_or_else(|| self.err("a string"), Ok)
    }

    fn opt_string(&self) -> R<Option<String>> {
        if self.is_null() {
            return Ok(None);
        }
        self.str().map(|s| Some(s.to_string()))
    }

    /// One of `names` (a `&'static str` of the report's vocabulary).
    fn name(&self, names: &[&'static str], expected: &'static str) -> R<&'static str> {
        let s = self.str()?;
        names
            .iter()
            .find(|n| **n == s)
            .copied()
            .map_or_else(|| self.err(expected), Ok)
    }

    pub(crate) fn array(&self) -> R<&'a [Value]> {
        self.value()
            .as_array()
            .map_or_else(|| self.err("an array"), |a| Ok(a.as_slice()))
    }
}

/// Reads the array `key` of `obj` at `path`, each element with `f`.
fn each<T>(obj: &Value, path: &str, key: &str, f: impl Fn(&Value, &str) -> R<T>) -> R<Vec<T>> {
    let at = At {
        v: obj.get(key),
        path,
        key,
    };
    at.array()?
        .iter()
        .enumerate()
        .map(|(i, v)| f(v, &format!("{path}.{key}[{i}]")))
        .collect()
}

/// The field `key` of `obj` (at `path`).
fn at<'a>(obj: &'a Value, path: &'a str, key: &'a str) -> At<'a> {
    At {
        v: obj.get(key),
        path,
        key,
    }
}

/// One route row read back from a report's `routes[i]` (`path` names it in errors); the
/// infraction counts are read apart, in the file's key order ([`InfractionCounts`]).
///
/// # Errors
/// [`FieldError`] for the first field that is not what a report writes.
pub fn row_from_json(v: &Value, path: &str, infractions: InfractionCounts) -> R<RouteReport> {
    if !v.is_object() {
        return At::new(v, path).err("a route object");
    }
    let f = |key| at(v, path, key);
    let reason = f("reason").opt_string()?;
    let sub = |key: &str| format!("{path}.{key}");
    let (cp, lp, mp) = (sub("collisions"), sub("lateral"), sub("comfort"));
    let c = v.get("collisions").unwrap_or(&Value::Null);
    let l = v.get("lateral").unwrap_or(&Value::Null);
    let m = v.get("comfort").unwrap_or(&Value::Null);
    let fp = format!("{mp}.failed");
    let failed = m.get("failed").unwrap_or(&Value::Null);
    let fc = |key| at(failed, &fp, key).u32();
    let telemetry = match f("telemetry").str()? {
        "ok" => TelemetryState::Ok,
        "missing" => TelemetryState::Missing(reason.clone().unwrap_or_default()),
        t => match t.strip_prefix("invalid: ") {
            Some(r) => TelemetryState::Invalid(r.to_string()),
            None => return f("telemetry").err("ok, missing or invalid: <reason>"),
        },
    };
    let state = match f("state").str()? {
        "scored" => RouteState::Scored,
        "missing" => RouteState::Missing,
        "foreign" => RouteState::Foreign,
        "invalid" => RouteState::Invalid(reason.clone().unwrap_or_default()),
        _ => return f("state").err("scored, missing, foreign or invalid"),
    };
    let source = source_of(v.get("source").unwrap_or(&Value::Null), &sub("source"))?;
    Ok(RouteReport {
        route_id: f("route_id").opt_string()?,
        scenario_type: f("scenario_type").opt_string()?,
        town: f("town").opt_string()?,
        weather_id: f("weather_id").opt_string()?,
        status: f("status").opt_string()?,
        success: f("success").bool()?,
        score_route: f("score_route").opt_f64()?,
        score_penalty: f("score_penalty").opt_f64()?,
        score_composed: f("score_composed").opt_f64()?,
        dt: f("dt").opt_f64()?,
        dt_source: match f("dt_source").value() {
            Value::Null => None,
            _ => Some(match f("dt_source").str()? {
                "inferred" => DtSource::Inferred,
                "config" => DtSource::Config,
                _ => return f("dt_source").err("inferred, config or null"),
            }),
        },
        frames: f("frames").u32()?,
        gaps: f("gaps").u64()?,
        segments: f("segments").opt_u64()?,
        infractions,
        distance_m: f("distance_m").opt_f64()?,
        stationary_share: f("stationary_share").opt_f64()?,
        collisions: CollisionCounts {
            pedestrian: at(c, &cp, "pedestrian").u32()?,
            vehicle: at(c, &cp, "vehicle").u32()?,
            layout: at(c, &cp, "layout").u32()?,
            workzone: at(c, &cp, "workzone").u32()?,
            unaligned: at(c, &cp, "unaligned").u32()?,
            exempt: at(c, &cp, "exempt").u32()?,
            nodecel: at(c, &cp, "nodecel").u32()?,
        },
        lateral: LateralReport {
            chunks: at(l, &lp, "chunks").u32()?,
            scored_chunks: at(l, &lp, "scored_chunks").u32()?,
            anomalous: at(l, &lp, "anomalous").u32()?,
            critical: at(l, &lp, "critical").u32()?,
            reference: match at(l, &lp, "reference").value() {
                Value::Null => None,
                _ => Some(
                    match at(l, &lp, "reference").name(
                        &["map-route", "xml", "map-lane", "none"],
                        "map-route, xml, map-lane, none or null",
                    )? {
                        "map-route" => ReferenceKind::MapRoute,
                        "xml" => ReferenceKind::Xml,
                        "map-lane" => ReferenceKind::MapLane,
                        _ => ReferenceKind::None,
                    },
                ),
            },
        },
        comfort: ComfortReport {
            chunks: at(m, &mp, "chunks").u32()?,
            comfortable: at(m, &mp, "comfortable").u32()?,
            score: at(m, &mp, "score").opt_f64()?,
            failed: monitor_core::FailureCounts {
                lon_acc: fc("lon_acc")?,
                lat_acc: fc("lat_acc")?,
                mag_jerk: fc("mag_jerk")?,
                lon_jerk: fc("lon_jerk")?,
                yaw_acc: fc("yaw_acc")?,
                yaw_rate: fc("yaw_rate")?,
            },
            moving_chunks: at(m, &mp, "moving_chunks").u32()?,
            moving_comfortable: at(m, &mp, "moving_comfortable").u32()?,
            moving_score: at(m, &mp, "moving_score").opt_f64()?,
        },
        smoothness: f("smoothness").opt_f64()?,
        efficiency: f("efficiency").opt_f64()?,
        ability: match v.get("ability") {
            None | Some(Value::Null) => None,
            Some(a) => Some(ability_of(a, &sub("ability"))?),
        },
        p_safe: f("p_safe").opt_f64()?,
        ds_safe: f("ds_safe").opt_f64()?,
        decomposition: match v.get("decomposition") {
            None | Some(Value::Null) => None,
            Some(d) => {
                let dp = sub("decomposition");
                let g = |k| at(d, &dp, k).f64();
                Some(Losses {
                    rounding: g("rounding")?,
                    workzone: g("workzone")?,
                    nodecel: g("nodecel")?,
                    anomalous: g("anomalous")?,
                    critical: g("critical")?,
                })
            }
        },
        min_speed_grid: match v.get("min_speed_grid") {
            None | Some(Value::Null) => None,
            Some(_) => Some(match f("min_speed_grid").str()? {
                "b2d-20" => MinSpeedGrid::B2d20,
                "lb-4" => MinSpeedGrid::Lb4,
                _ => return f("min_speed_grid").err("b2d-20 or lb-4"),
            }),
        },
        protocols: match v.get("protocols") {
            None | Some(Value::Null) => None,
            Some(p) => Some(protocols_of(p, &sub("protocols"))?),
        },
        telemetry,
        state,
        reason,
        kept: match v.get("kept") {
            None | Some(Value::Null) => None,
            Some(k) => Some(kept_of(
                k,
                &sub("kept"),
                source.clone().unwrap_or(Source {
                    file: Default::default(),
                    index: 0,
                }),
            )?),
        },
        source,
        stamp: match f("stamp").opt_string()? {
            Some(s) if crate::input::duplicates::parse_stamp(&s).is_none() => {
                return f("stamp").err("a save_name time stamp mm_dd_HH_MM_SS")
            }
            s => s,
        },
        collision_events: each(v, path, "collision_events", collision_of)?,
        events: each(v, path, "events", event_of)?,
        penalty_check: match v.get("penalty_check") {
            None | Some(Value::Null) => None,
            Some(p) => {
                let pp = sub("penalty_check");
                Some(PenaltyReport {
                    recomputed: at(p, &pp, "recomputed").f64()?,
                    agrees: at(p, &pp, "agrees").bool()?,
                })
            }
        },
        batch_agrees: f("batch_agrees").opt_bool()?,
        warnings: match v.get("warnings") {
            None => Vec::new(),
            Some(_) => each(v, path, "warnings", |w, p| {
                At::new(w, p)
                    .str()
                    .map(|s| Warning::Recorded(s.to_string()))
            })?,
        },
        traces: Vec::new(),
        chunks: None,
        stationary: Vec::new(),
        driven_km: f("driven_km").opt_f64()?,
    })
}

fn source_of(v: &Value, path: &str) -> R<Option<Source>> {
    if v.is_null() {
        return Ok(None);
    }
    Ok(Some(Source {
        file: at(v, path, "file").str()?.into(),
        index: at(v, path, "index").usize()?,
    }))
}

/// A `{"file", "index"}` source (the report's `dropped[]` entries use it too).
pub(crate) fn required_source(v: &Value, path: &str) -> R<Source> {
    source_of(v, path)?.map_or_else(|| At::new(v, path).err("a source object"), Ok)
}

fn kept_of(v: &Value, path: &str, source: Source) -> R<Kept> {
    let policy = at(v, path, "policy").str()?;
    let Some(p) = DuplicatePolicy::from_name(policy) else {
        return at(v, path, "policy").err("a duplicates policy");
    };
    Ok(Kept {
        policy: p.name(),
        copies: at(v, path, "copies").usize()?,
        stamp: at(v, path, "stamp").opt_string()?,
        why: at(v, path, "why").str()?.to_string(),
        source,
        by_order: false,
        year_wrap: false,
    })
}

fn ability_of(v: &Value, path: &str) -> R<RouteAbility> {
    let names: Vec<&'static str> = ABILITIES.iter().map(|(n, _)| *n).collect();
    Ok(RouteAbility {
        scenario_type: at(v, path, "scenario_type").str()?.to_string(),
        abilities: each(v, path, "abilities", |e, p| {
            Ok(AbilityEntry {
                ability: at(e, p, "ability").name(&names, "an ability name")?,
                success: at(e, p, "success").bool()?,
                second_count: at(e, p, "second_count").opt_bool()?.unwrap_or(false),
            })
        })?,
        junction: match v.get("junction") {
            None | Some(Value::Null) => None,
            Some(j) => {
                let jp = format!("{path}.junction");
                Some(match j.get("undecided") {
                    Some(_) => JunctionCredit::Undecided {
                        undecided: at(j, &jp, "undecided").str()?.to_string(),
                    },
                    None => JunctionCredit::Decided {
                        score: at(j, &jp, "score").f64()?,
                        junction_completion: at(j, &jp, "junction_completion").f64()?,
                        credited: at(j, &jp, "credited").bool()?,
                        marginal: at(j, &jp, "marginal").bool()?,
                    },
                })
            }
        },
    })
}

/// The per-route protocols, in [`Protocol::ALL`] order (the order `sds score` writes).
fn protocols_of(v: &Value, path: &str) -> R<RouteProtocols> {
    let Some(map) = v.as_object() else {
        return At::new(v, path).err("an object of protocols");
    };
    let mut out = Vec::new();
    for p in Protocol::ALL {
        let Some(s) = map.get(p.id()) else { continue };
        let sp = format!("{path}.{}", p.id());
        out.push((
            p,
            RouteScore {
                penalty: at(s, &sp, "penalty").opt_f64()?,
                score: at(s, &sp, "score").f64()?,
                success: at(s, &sp, "success").bool()?,
                min_speed_events: at(s, &sp, "min_speed_events").usize()?,
            },
        ));
    }
    if let Some(k) = map.keys().find(|k| Protocol::from_id(k).is_none()) {
        return Err(FieldError {
            path: format!("{path}.{k}"),
            expected: "a protocol id (b2d, lb2.0, lb2.1, lead-nds, f2d)",
        });
    }
    Ok(RouteProtocols(out))
}

fn collision_of(v: &Value, path: &str) -> R<CollisionEvent> {
    let f = |key| at(v, path, key);
    let Some(list) = CollisionList::from_name(f("list").str()?) else {
        return f("list").err("a collision list name");
    };
    Ok(CollisionEvent {
        list,
        type_id: f("type_id").opt_string()?,
        workzone: f("workzone").bool()?,
        frame: f("frame").opt_usize()?,
        step: f("step").opt_u64()?,
        aligned_by: match f("aligned_by").value() {
            Value::Null => None,
            _ => Some(match f("aligned_by").str()? {
                "nearest" => AlignedBy::Nearest,
                "infractions.json" => AlignedBy::InfractionsJson,
                "log time" => AlignedBy::LogTime,
                _ => return f("aligned_by").err("nearest, infractions.json, log time or null"),
            }),
        },
        time_s: f("time_s").opt_f64()?,
        // An f32 written by the report reads back exactly through f64.
        impact_speed: f("impact_speed").opt_f64()?.map(|x| x as f32),
        decelerated: f("decelerated").opt_bool()?,
        exempt: f("exempt").opt_bool()?,
        parse_error: f("parse_error").opt_string()?,
        message: String::new(),
        location: None,
    })
}

fn event_of(v: &Value, path: &str) -> R<RouteEvent> {
    let f = |key| at(v, path, key);
    Ok(RouteEvent {
        kind: f("kind").name(&EVENT_KINDS, "an event kind")?,
        list: f("list").opt_string()?,
        frame: f("frame").opt_usize()?,
        end_frame: f("end_frame").opt_usize()?,
        step: f("step").opt_u64()?,
        time_s: f("time_s").opt_f64()?,
        placed_by: match f("placed_by").value() {
            Value::Null => None,
            _ => Some(f("placed_by").name(&PLACED_BY, "how an event is placed")?),
        },
        distance_m: f("distance_m").opt_f64()?,
        collision: f("collision").opt_usize()?,
        message: f("message").str()?.to_string(),
    })
}

/// The `infractions` object of every route of a report, in the file's key order (a
/// `serde_json::Value` sorts its keys; the report's order is Bench2Drive's lists, then unknown
/// ones in record order).
#[derive(serde::Deserialize)]
pub(crate) struct RoutesInfractions {
    pub routes: Vec<RowInfractions>,
}

/// One route's `infractions`.
#[derive(serde::Deserialize)]
pub(crate) struct RowInfractions {
    #[serde(default, deserialize_with = "ordered_counts")]
    pub infractions: Vec<(String, usize)>,
}

fn ordered_counts<'de, D: serde::Deserializer<'de>>(
    d: D,
) -> Result<Vec<(String, usize)>, D::Error> {
    struct V;
    impl<'de> serde::de::Visitor<'de> for V {
        type Value = Vec<(String, usize)>;
        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            f.write_str("an object of infraction counts")
        }
        fn visit_map<A: serde::de::MapAccess<'de>>(
            self,
            mut m: A,
        ) -> Result<Self::Value, A::Error> {
            let mut out = Vec::new();
            while let Some((k, v)) = m.next_entry::<String, usize>()? {
                out.push((k, v));
            }
            Ok(out)
        }
    }
    d.deserialize_map(V)
}
