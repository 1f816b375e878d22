//! How far a comparison's conclusions depend on the definition's own numbers (`sds compare
//! --sweep NAME=V1,V2,...`, docs/SCORE.md "The sweep"): the grid of settings ([`grid`]), and per
//! point each model's DS_safe, comfort, SDS and rank by SDS; per model the range of its SDS; per
//! pair of models whether their order holds over the grid ([`SweepReport`]).
//!
//! ```
//! use monitor_host::stats::sweep::{grid, SweepAxis};
//! use monitor_host::Settings;
//! let axes = [
//!     SweepAxis::parse("critical_excess=0.5,0.65")?,
//!     SweepAxis::parse("factors.critical=0.8,0.9,1")?,
//! ];
//! let points = grid(&Settings::default(), &axes)?;
//! assert_eq!(points.len(), 6); // 2 x 3, the last setting varying fastest
//! assert_eq!(points[1].get("factors.critical").as_deref(), Some("0.9"));
//! assert!(grid(&Settings::default(), &[SweepAxis::parse("protocols=all,none")?])
//!     .unwrap_err().to_string().contains("critical_excess"));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use serde::ser::SerializeMap;
use serde::Serialize;

use crate::settings::defs::{self, sweep_names, Sweep, Value};
use crate::settings::Settings;

/// Most points a sweep scores: each point scores every run again **\[decision\]**.
pub const MAX_POINTS: usize = 64;

/// One `--sweep NAME=V1,V2,...`: a setting and the values it takes over the grid.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SweepAxis {
    /// The setting's name.
    pub name: String,
    /// Its values, as written.
    pub values: Vec<String>,
}

impl SweepAxis {
    /// Reads `NAME=V1,V2,...`.
    ///
    /// # Errors
    /// [`SweepError::Syntax`] without `=` or with an empty value.
    pub fn parse(text: &str) -> Result<SweepAxis, SweepError> {
        let syntax = || SweepError::Syntax(text.to_string());
        let (name, list) = text.split_once('=').ok_or_else(syntax)?;
        let values: Vec<String> = list.split(',').map(|v| v.trim().to_string()).collect();
        if name.trim().is_empty() || values.iter().any(String::is_empty) {
            return Err(syntax());
        }
        Ok(SweepAxis {
            name: name.trim().to_string(),
            values,
        })
    }

    /// One axis from a setting's name and its values, each written as `--sweep` writes it
    /// (front ends that take a mapping, as Python's `sds.compare(sweep=...)`), checked by
    /// [`SweepAxis::parse`] itself so that every front end refuses what `--sweep` refuses.
    ///
    /// ```
    /// use monitor_host::stats::sweep::SweepAxis;
    /// assert_eq!(SweepAxis::new("slack", &["0.5", "0.9"])?, SweepAxis::parse("slack=0.5,0.9")?);
    /// assert!(SweepAxis::new("slack", &[" "]).is_err());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    ///
    /// # Errors
    /// [`SweepError::Syntax`] for an empty name or value, no values, or what `NAME=V1,V2,...`
    /// cannot say (a name holding `=`, a value holding `,`).
    pub fn new<S: AsRef<str>>(name: &str, values: &[S]) -> Result<SweepAxis, SweepError> {
        let values: Vec<&str> = values.iter().map(AsRef::as_ref).collect();
        let text = format!("{name}={}", values.join(","));
        let axis = SweepAxis::parse(&text)?;
        // Read back as the command line reads it: a `=` in the name or a `,` in a value would
        // make other settings or more values than were given.
        if axis.name != name.trim() || axis.values.len() != values.len() {
            return Err(SweepError::Syntax(text));
        }
        Ok(axis)
    }
}

/// Why a sweep was refused (before any run is scored).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SweepError {
    /// Not `NAME=V1,V2,...`.
    #[error("sweep {0}: expected NAME=V1,V2,... (a setting and its values, comma-separated)")]
    Syntax(String),
    /// The name is no setting, or one that changes no route's figures.
    #[error(
        "sweep {name}: {why}; a sweep takes a setting that changes a route's DS_safe or \
         comfort: {}", sweep_names().join(", ")
    )]
    NotSweepable {
        /// The name given.
        name: String,
        /// `no such setting`, or `changes no route's figures (group ...)`.
        why: String,
    },
    /// The same setting twice.
    #[error("sweep {0} is given twice: list all its values in one NAME=V1,V2,...")]
    Twice(String),
    /// A value the setting refuses (the point's settings as a whole included).
    #[error("sweep {name}={value}: {error}")]
    Value {
        /// The setting.
        name: String,
        /// The value.
        value: String,
        /// Why.
        error: crate::settings::SettingsError,
    },
    /// More points than [`MAX_POINTS`].
    #[error(
        "sweep: the grid has {points} points ({sizes}); at most {MAX_POINTS}: \
         give fewer values",
        sizes = sizes.iter().map(ToString::to_string).collect::<Vec<_>>().join(" x ")
    )]
    TooManyPoints {
        /// The product of the sizes.
        points: usize,
        /// Each setting's number of values.
        sizes: Vec<usize>,
    },
    /// A run given as a report: it cannot be scored again.
    #[error(
        "sweep: run {run} is a report ({file}): a sweep scores every run again at every point; \
         give the run's results (and telemetry) instead"
    )]
    Report {
        /// The run.
        run: String,
        /// Its report file.
        file: String,
    },
}

/// The settings at every point of the grid: `base` with each axis' value set, in order, the
/// last axis varying fastest.
///
/// # Errors
/// [`SweepError`]: an axis' name or value refused, a name twice, more than [`MAX_POINTS`].
pub fn grid(base: &Settings, axes: &[SweepAxis]) -> Result<Vec<Settings>, SweepError> {
    for (i, a) in axes.iter().enumerate() {
        match defs::def(&a.name) {
            None => {
                return Err(SweepError::NotSweepable {
                    name: a.name.clone(),
                    why: "no such setting".into(),
                })
            }
            Some(d) if d.sweep == Sweep::No => {
                return Err(SweepError::NotSweepable {
                    name: a.name.clone(),
                    why: format!("changes no route's figures (group {})", d.group),
                })
            }
            Some(_) => {}
        }
        if axes[..i].iter().any(|b| b.name == a.name) {
            return Err(SweepError::Twice(a.name.clone()));
        }
    }
    let sizes: Vec<usize> = axes.iter().map(|a| a.values.len()).collect();
    let points = sizes
        .iter()
        .try_fold(1usize, |n, s| n.checked_mul(*s))
        .unwrap_or(usize::MAX);
    if points > MAX_POINTS {
        return Err(SweepError::TooManyPoints { points, sizes });
    }
    let mut out = vec![base.clone()];
    for a in axes {
        let mut next = Vec::with_capacity(out.len() * a.values.len());
        for s in &out {
            for v in &a.values {
                let mut p = s.clone();
                p.set(&a.name, v).map_err(|error| SweepError::Value {
                    name: a.name.clone(),
                    value: v.clone(),
                    error,
                })?;
                next.push(p);
            }
        }
        out = next;
    }
    Ok(out)
}

/// The sweep's report: `sweep` in the `sds-compare/1` report.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SweepReport {
    /// The settings swept, in the order given.
    pub settings: Vec<String>,
    /// Every point of the grid, the last setting varying fastest.
    pub points: Vec<SweepPoint>,
    /// Per pair of models (in model order: a before b), whether their order holds.
    pub pairs: Vec<SweepPair>,
    /// Per model, the range of its SDS over the grid.
    pub ranges: Vec<SweepRange>,
}

/// One point: the swept settings' values and each model's figures there.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepPoint {
    /// Each swept setting's value (as the report's `config` writes it), in the order given.
    pub values: Vec<(String, Value)>,
    /// Each model's figures, in model order.
    pub models: Vec<SweepFigures>,
}

impl Serialize for SweepPoint {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        struct Values<'a>(&'a [(String, Value)]);
        impl Serialize for Values<'_> {
            fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
                let mut m = s.serialize_map(Some(self.0.len()))?;
                for (k, v) in self.0 {
                    m.serialize_entry(k, v)?;
                }
                m.end()
            }
        }
        let mut m = s.serialize_map(Some(2))?;
        m.serialize_entry("values", &Values(&self.values))?;
        m.serialize_entry("models", &self.models)?;
        m.end()
    }
}

/// One model at one point: its figures as `sds compare` reports them (the mean over its seeds).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SweepFigures {
    /// The model.
    pub model: String,
    /// Mean DS_safe.
    pub ds_safe: Option<f64>,
    /// Mean comfort.
    pub comfort: Option<f64>,
    /// SDS.
    pub sds: Option<f64>,
    /// 1 + the number of models with a strictly greater SDS (null without an SDS).
    pub rank: Option<usize>,
}

/// Whether two models keep their order by SDS over the grid.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SweepPair {
    /// The first model.
    pub a: String,
    /// The second.
    pub b: String,
    /// The same order (a above, b above, tied, or unknown without an SDS) at every point.
    pub order_stable: bool,
    /// The points whose order differs from the point before's (indices into `points`).
    pub flips: Vec<usize>,
}

/// A model's lowest and highest SDS over the grid (null when some point has none).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SweepRange {
    /// The model.
    pub model: String,
    /// Lowest SDS.
    pub sds_min: Option<f64>,
    /// Highest SDS.
    pub sds_max: Option<f64>,
}

/// The report from each point's values and figures (`[ds_safe, comfort, sds]` per model, in
/// model order).
///
/// ```
/// use monitor_host::stats::sweep::report;
/// use monitor_host::settings::defs::Value;
/// let at = |v: f32| vec![("critical_excess".to_string(), Value::F32(v))];
/// let r = report(
///     &["critical_excess".into()],
///     &["a".into(), "b".into()],
///     vec![
///         (at(0.5), vec![[Some(60.0), Some(0.9), Some(54.0)], [Some(58.0), Some(0.9), Some(52.2)]]),
///         (at(0.65), vec![[Some(60.0), Some(0.8), Some(48.0)], [Some(58.0), Some(0.9), Some(52.2)]]),
///     ],
/// );
/// assert_eq!(r.points[1].models[1].rank, Some(1));
/// assert_eq!((r.pairs[0].order_stable, r.pairs[0].flips.clone()), (false, vec![1]));
/// assert_eq!((r.ranges[0].sds_min, r.ranges[0].sds_max), (Some(48.0), Some(54.0)));
/// ```
#[allow(clippy::type_complexity)]
pub fn report(
    settings: &[String],
    models: &[String],
    points: Vec<(Vec<(String, Value)>, Vec<[Option<f64>; 3]>)>,
) -> SweepReport {
    let points: Vec<SweepPoint> = points
        .into_iter()
        .map(|(values, figures)| {
            let sds: Vec<Option<f64>> = figures.iter().map(|f| f[2]).collect();
            let models = models
                .iter()
                .zip(&figures)
                .map(|(m, f)| SweepFigures {
                    model: m.clone(),
                    ds_safe: f[0],
                    comfort: f[1],
                    sds: f[2],
                    rank: f[2].map(|x| 1 + sds.iter().flatten().filter(|y| **y > x).count()),
                })
                .collect();
            SweepPoint { values, models }
        })
        .collect();
    let sds = |p: &SweepPoint, m: usize| p.models.get(m).and_then(|f| f.sds);
    let mut pairs = Vec::new();
    for a in 0..models.len() {
        for b in a + 1..models.len() {
            // Some(Ordering) of a against b, None without both SDS.
            let order = |p: &SweepPoint| match (sds(p, a), sds(p, b)) {
                (Some(x), Some(y)) => x.partial_cmp(&y),
                _ => None,
            };
            let flips: Vec<usize> = (1..points.len())
                .filter(|&i| order(&points[i]) != order(&points[i - 1]))
                .collect();
            pairs.push(SweepPair {
                a: models[a].clone(),
                b: models[b].clone(),
                order_stable: flips.is_empty(),
                flips,
            });
        }
    }
    let ranges = models
        .iter()
        .enumerate()
        .map(|(m, name)| {
            let all: Option<Vec<f64>> = points.iter().map(|p| sds(p, m)).collect();
            let all = all.filter(|v| !v.is_empty());
            SweepRange {
                model: name.clone(),
                sds_min: all
                    .as_ref()
                    .map(|v| v.iter().copied().fold(f64::INFINITY, f64::min)),
                sds_max: all.map(|v| v.iter().copied().fold(f64::NEG_INFINITY, f64::max)),
            }
        })
        .collect();
    SweepReport {
        settings: settings.to_vec(),
        points,
        pairs,
        ranges,
    }
}

/// Each swept setting's value at a point.
pub fn values_at(settings: &[String], point: &Settings) -> Vec<(String, Value)> {
    settings
        .iter()
        .filter_map(|n| point.value(n).map(|v| (n.clone(), v)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Issue 48 item 1: an axis given as name and values (Python's `sweep={...}`) is checked
    /// by `--sweep`'s own parser: what the flag refuses is refused, what it takes is equal.
    #[test]
    fn i48_1_axis_from_values_is_checked_as_the_flag_is() {
        assert_eq!(
            SweepAxis::new(" slack ", &["0.5", " 0.9"]),
            SweepAxis::parse("slack=0.5,0.9")
        );
        let none: [&str; 0] = [];
        for (name, values) in [
            ("", &["0.5"][..]),
            (" ", &["0.5"][..]),
            ("slack", &[""][..]),
            ("slack", &["0.5", " "][..]),
            ("slack", &none[..]),
            ("slack", &["0.5,0.9"][..]),
            ("slack=0.5", &["0.9"][..]),
        ] {
            let e = SweepAxis::new(name, values).unwrap_err();
            assert!(
                matches!(e, SweepError::Syntax(_)),
                "{name:?} {values:?}: {e}"
            );
            assert!(e.to_string().contains("expected NAME=V1,V2"), "{e}");
        }
    }

    fn axis(name: &str, n: usize) -> SweepAxis {
        SweepAxis {
            name: name.into(),
            values: (0..n).map(|i| format!("0.{}", i + 1)).collect(),
        }
    }

    #[test]
    fn sixty_four_points_are_taken_sixty_five_refused_with_the_count() {
        let base = Settings::default();
        let ok = grid(
            &base,
            &[axis("factors.critical", 8), axis("factors.anomalous", 8)],
        );
        assert_eq!(ok.map(|g| g.len()), Ok(64));
        let e = grid(&base, &[axis("factors.critical", 5), axis("slack", 13)]).unwrap_err();
        assert_eq!(
            e,
            SweepError::TooManyPoints {
                points: 65,
                sizes: vec![5, 13]
            }
        );
    }

    #[test]
    fn every_listed_setting_changes_a_figure_stage() {
        // The list comes from the rows: each name is a setting whose row is not `No`.
        for n in sweep_names() {
            assert_ne!(defs::def(n).map(|d| d.sweep), Some(Sweep::No), "{n}");
        }
        assert!(!sweep_names().contains(&"motion.moving_speed"));
    }
}
