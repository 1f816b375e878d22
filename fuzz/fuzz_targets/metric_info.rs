//! `monitor_host::input::metric_info::parse_metric_info` on arbitrary bytes: never panics, and what it
//! accepts satisfies the spec's invariants (sorted unique steps, finite values, gap count). Its
//! fast path (the scanner) never accepts what the serde_json visitor rejects, nor reads a value
//! differently (bit for bit).
#![no_main]

use libfuzzer_sys::fuzz_target;
use monitor_host::geometry::kinematics::speeds;
use monitor_host::input::metric_info::{
    parse_metric_info, parse_metric_info_fast, parse_metric_info_serde, Telemetry,
};

/// Every number as bits, with the steps and the gap count.
fn bits(t: &Telemetry) -> (u64, Vec<[u64; 10]>) {
    let frames = t
        .frames
        .iter()
        .map(|f| {
            [
                f.step,
                f.location[0].to_bits(),
                f.location[1].to_bits(),
                u64::from(f.acc[0].to_bits()),
                u64::from(f.acc[1].to_bits()),
                u64::from(f.fwd[0].to_bits()),
                u64::from(f.fwd[1].to_bits()),
                u64::from(f.right[0].to_bits()),
                u64::from(f.right[1].to_bits()),
                u64::from(f.yaw_rate_deg.to_bits()),
            ]
        })
        .collect();
    (t.gaps, frames)
}

fuzz_target!(|data: &[u8]| {
    if let Some(fast) = parse_metric_info_fast(data) {
        let serde =
            parse_metric_info_serde(data).expect("the fast path accepted what serde rejects");
        assert_eq!(bits(&fast), bits(&serde));
    }
    match parse_metric_info(data) {
        Ok(t) => {
            assert!(!t.frames.is_empty());
            assert!(t.frames.windows(2).all(|w| w[0].step < w[1].step));
            let first = t.frames[0].step;
            let last = t.frames[t.frames.len() - 1].step;
            assert_eq!(t.gaps, last - first + 1 - t.frames.len() as u64);
            for f in &t.frames {
                assert!(f.location.iter().all(|v| v.is_finite()));
                assert!(f
                    .acc
                    .iter()
                    .chain(&f.fwd)
                    .chain(&f.right)
                    .all(|v| v.is_finite()));
                assert!(f.yaw_rate_deg.is_finite());
            }
            // Speeds of accepted telemetry are computed without panicking.
            let _ = speeds(&t.frames, 0.05);
        }
        Err(e) => {
            // Every error has a non-empty message (it becomes `invalid: <reason>`).
            assert!(!e.to_string().is_empty());
        }
    }
});
