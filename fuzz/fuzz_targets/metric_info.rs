//! `monitor_host::input::metric_info::parse_metric_info` on arbitrary bytes: never panics, and what it
//! accepts satisfies the spec's invariants (sorted unique steps, finite values, gap count).
#![no_main]

use libfuzzer_sys::fuzz_target;
use monitor_host::geometry::kinematics::speeds;
use monitor_host::input::metric_info::parse_metric_info;

fuzz_target!(|data: &[u8]| {
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
