//! The step period of a route (docs/SCORE.md §2.2) **\[decision\]**: CARLA ticks at 20 Hz,
//! but agents do not all write a telemetry frame every tick (real published `metric_info.json`
//! exists at 10 Hz). The period is inferred per route from the record's `meta.duration_game` and
//! the telemetry's step span, unless a fixed `dt` is set.
//!
//! The period is configuration handed to the route's [`monitor_core::Config`] once, before the
//! first frame: nothing of the monitor's per-frame work changes.
//!
//! ```
//! use monitor_host::pipeline::step_period::{infer, DtSource};
//! use monitor_host::Settings;
//! // 1,337 steps for 133.8 s of game time: one step per 0.1 s.
//! let (p, w) = infer(1, 1337, 0, Some(133.8), &Settings::default());
//! assert_eq!((p.dt, p.source), (0.1, DtSource::Inferred));
//! assert!(w.is_empty());
//! ```

use crate::input::warning::Warning;
use crate::settings::{decimal, Settings};

/// The CARLA tick the periods are multiples of, s.
pub(crate) const TICK: f64 = 0.05;
/// Fewest steps for an inference.
const MIN_SPAN: u64 = 20;

/// Where a route's `dt` came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum DtSource {
    /// From `meta.duration_game` / step span.
    Inferred,
    /// The `dt` setting.
    Config,
}

/// A route's step period.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepPeriod {
    /// Seconds per step, as the decimal a person writes (`0.1`).
    pub dt: f64,
    /// Where it came from.
    pub source: DtSource,
}

impl StepPeriod {
    /// The period as the monitor's f32 (the setting itself when it came from the config, so
    /// that a fixed `dt` reaches the monitor bit for bit).
    pub fn as_f32(&self, settings: &Settings) -> f32 {
        match self.source {
            DtSource::Config => settings.core.dt,
            DtSource::Inferred => self.dt as f32,
        }
    }
}

/// Infers the period of a route whose telemetry spans steps `first..=last` with `gaps` missing
/// step numbers and whose record says `duration_game` seconds. Returns the period and the
/// warnings it gives (no multiple of the tick fits; gaps above 10 % of the span).
pub fn infer(
    first: u64,
    last: u64,
    gaps: u64,
    duration_game: Option<f64>,
    settings: &Settings,
) -> (StepPeriod, Vec<Warning>) {
    let span = last.saturating_sub(first).saturating_add(1);
    let mut warnings = Vec::new();
    let large_gaps = gaps.saturating_mul(10) > span;
    let config = StepPeriod {
        dt: decimal(settings.core.dt),
        source: DtSource::Config,
    };
    let duration = duration_game.filter(|d| d.is_finite() && *d > 0.0);
    let Some(d) = duration.filter(|_| settings.dt_inference && span >= MIN_SPAN) else {
        if large_gaps {
            warnings.push(Warning::LargeGaps { gaps, span });
        }
        return (config, warnings);
    };
    // v1.3: a file holding only part of the run cannot tell its period (steps 480..810 of a
    // 10 Hz run of 0..1336 would read as 0.4 s).
    if large_gaps {
        warnings.push(Warning::StepPeriodPartial {
            gaps,
            span,
            dt: config.dt,
        });
        return (config, warnings);
    }
    let r = d / span as f64;
    let k = (r / TICK).round(); // f64::round: half away from zero
    if k >= 1.0 && (r - TICK * k).abs() <= 0.01 * k {
        // 5k / 100 rounds to the decimal (0.15, not 0.15000000000000002).
        let dt = 5.0 * k / 100.0;
        return (
            StepPeriod {
                dt,
                source: DtSource::Inferred,
            },
            warnings,
        );
    }
    warnings.push(Warning::StepPeriodUnknown {
        span,
        duration_game: d,
        dt: config.dt,
    });
    (config, warnings)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inference_rules() {
        let s = Settings::default();
        let inferred = |dt| StepPeriod {
            dt,
            source: DtSource::Inferred,
        };
        let config = StepPeriod {
            dt: 0.05,
            source: DtSource::Config,
        };
        assert_eq!(infer(1, 100, 0, Some(5.0), &s).0, inferred(0.05));
        assert_eq!(infer(1, 100, 0, Some(10.0), &s).0, inferred(0.1));
        assert_eq!(infer(1, 100, 0, Some(15.0), &s).0, inferred(0.15));
        // within 20 %: r = 0.059 fits k = 1 (|0.009| <= 0.01)
        assert_eq!(infer(1, 100, 0, Some(5.9), &s).0, inferred(0.05));
        // r = 0.075: k = round(1.5) = 2, |0.075 - 0.1| = 0.025 > 0.02: no fit, a warning
        let (p, w) = infer(1, 100, 0, Some(7.5), &s);
        assert_eq!(p, config);
        assert!(w[0].to_string().contains("setting dt="), "{}", w[0]);
        // too short, no duration, zero duration: the setting, silently
        assert_eq!(infer(1, 19, 0, Some(1.9), &s), (config, vec![]));
        assert_eq!(infer(1, 100, 0, None, &s), (config, vec![]));
        assert_eq!(infer(1, 100, 0, Some(0.0), &s), (config, vec![]));
        // r tiny: k = 0
        assert_eq!(infer(1, 1000, 0, Some(1.0), &s).0, config);
        // gaps above 10 % of the span: no inference, one warning naming --set dt=
        let (p, w) = infer(1, 100, 11, Some(5.0), &s);
        assert_eq!((p, w.len()), (config, 1));
        let text = w[0].to_string();
        assert!(
            text.contains("11 of 100") && text.contains("setting dt="),
            "{text}"
        );
        assert!(text.contains("not inferred"), "{text}");
        assert_eq!(infer(1, 100, 10, Some(5.0), &s), (inferred(0.05), vec![]));
        // issue 23: a 10 Hz route whose file holds steps 480..=810 (287 of 331 missing) of a
        // 133.6 s run read as 0.4 s; now the setting, with the warning
        let (p, w) = infer(480, 810, 287, Some(133.6), &s);
        assert_eq!(p, config);
        assert!(matches!(
            w[..],
            [Warning::StepPeriodPartial {
                gaps: 287,
                span: 331,
                ..
            }]
        ));
        // without a duration the gaps still warn (chunks span missing time)
        let (p, w) = infer(1, 100, 11, None, &s);
        assert_eq!(p, config);
        assert!(matches!(w[..], [Warning::LargeGaps { .. }]));
        // a fixed dt turns inference off
        let mut fixed = Settings::default();
        fixed.set("dt", "0.1").unwrap();
        let (p, _) = infer(1, 100, 0, Some(5.0), &fixed);
        assert_eq!(
            (p.dt, p.source, p.as_f32(&fixed)),
            (0.1, DtSource::Config, 0.1f32)
        );
    }
}
