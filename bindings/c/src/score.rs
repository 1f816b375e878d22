//! Scores of one route: the comfort score and DS_safe.

use monitor_core::{score, Factors, RouteSummary};

use crate::config::sds_factors;
use crate::result::sds_result;
use crate::summary::sds_summary;
use crate::{guard, usable};

/// What the evaluator recorded for the route, plus its work-zone count.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[allow(non_camel_case_types)]
pub struct sds_record_scores {
    /// `scores.score_route` (0..100).
    pub score_route: f64,
    /// `scores.score_penalty`.
    pub score_penalty: f64,
    /// Work-zone contacts among the layout collisions, aligned or not (`N_wz`).
    pub workzone: u32,
}

/// The route's safe scores.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[allow(non_camel_case_types)]
pub struct sds_safe_score {
    /// `p_safe = score_penalty * (workzone / layout)^N_wz`.
    pub p_safe: f64,
    /// `DS_safe = score_route * p_safe * nodecel^N_nodecel * anomalous^N_anom * critical^N_crit`.
    pub ds_safe: f64,
}

/// The comfort score `comfortable / chunks` into `*score`; `SDS_RESULT_UNDEFINED` (and NaN) when
/// the route has no comfort chunk (fewer than `min_chunk` frames).
///
/// ```c
/// double c;
/// if (sds_summary_comfort_score(&s, &c) == SDS_RESULT_UNDEFINED) { /* no comfort chunk */ }
/// ```
///
/// # Safety
/// `summary` is NULL or points to a readable `sds_summary`; `score` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn sds_summary_comfort_score(
    summary: *const sds_summary,
    score: *mut f64,
) -> sds_result {
    guard(|| {
        if let Err(e) = usable(summary).and(usable(score)) {
            return e;
        }
        // SAFETY: usable; the caller promises a readable sds_summary (plain integers).
        let s = RouteSummary::from(unsafe { &*summary });
        let (value, r) = match s.comfort_score() {
            Some(v) => (v, sds_result::Ok),
            None => (f64::NAN, sds_result::Undefined),
        };
        // SAFETY: usable; the caller promises a writable double.
        unsafe { score.write(value) };
        r
    })
}

/// DS_safe of one route (multiplied left to right as the spec writes it, so the bits equal the
/// Rust tools').
///
/// ```c
/// sds_record_scores rec = {80.0, 1.0, 0};   /* score_route, score_penalty, work-zone hits */
/// sds_config c = sds_config_default();
/// sds_safe_score out;
/// sds_ds_safe(&s, &rec, &c.factors, &out);  /* out.ds_safe */
/// ```
///
/// # Safety
/// Each pointer is NULL or points to a readable (`out`: writable) value of its type.
#[no_mangle]
pub unsafe extern "C" fn sds_ds_safe(
    summary: *const sds_summary,
    record: *const sds_record_scores,
    factors: *const sds_factors,
    out: *mut sds_safe_score,
) -> sds_result {
    guard(|| {
        if let Err(e) = usable(summary)
            .and(usable(record))
            .and(usable(factors))
            .and(usable(out))
        {
            return e;
        }
        // SAFETY: all usable; the caller promises readable values (plain numbers).
        let (s, r, f) = unsafe { (summary.read(), record.read(), factors.read()) };
        let record = score::RecordScores {
            score_route: r.score_route,
            score_penalty: r.score_penalty,
            workzone: r.workzone,
        };
        let safe = score::ds_safe(&RouteSummary::from(&s), &record, &Factors::from(f));
        let value = sds_safe_score {
            p_safe: safe.p_safe,
            ds_safe: safe.ds_safe,
        };
        // SAFETY: usable; the caller promises a writable sds_safe_score.
        unsafe { out.write(value) };
        sds_result::Ok
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::sds_config_default;

    #[test]
    fn ds_safe_is_the_core_s() {
        let mut s = sds_summary::default();
        s.collisions.nodecel = 1;
        s.lateral.critical = 2;
        let r = sds_record_scores {
            score_route: 80.0,
            score_penalty: 0.65,
            workzone: 1,
        };
        let f = sds_config_default().factors;
        let mut out = sds_safe_score::default();
        // SAFETY: valid pointers to locals.
        assert_eq!(unsafe { sds_ds_safe(&s, &r, &f, &mut out) }, sds_result::Ok);
        let core = score::ds_safe(
            &RouteSummary::from(&s),
            &score::RecordScores {
                score_route: 80.0,
                score_penalty: 0.65,
                workzone: 1,
            },
            &Factors::DEFAULT,
        );
        assert_eq!(out.ds_safe.to_bits(), core.ds_safe.to_bits());
        assert_eq!(out.p_safe.to_bits(), core.p_safe.to_bits());
    }

    #[test]
    fn comfort_score_undefined_without_chunks() {
        let mut s = sds_summary::default();
        let mut v = 0.0;
        // SAFETY: valid pointers to locals.
        assert_eq!(
            unsafe { sds_summary_comfort_score(&s, &mut v) },
            sds_result::Undefined
        );
        assert!(v.is_nan());
        s.comfort.chunks = 4;
        s.comfort.comfortable = 3;
        // SAFETY: as above.
        assert_eq!(
            unsafe { sds_summary_comfort_score(&s, &mut v) },
            sds_result::Ok
        );
        assert_eq!(v, 0.75);
    }
}
