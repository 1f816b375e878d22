//! `monitor_core::json::decode_frame` on arbitrary bytes, then every decoded frame pushed into a
//! monitor. The monitor must never panic: a refused frame leaves its state unchanged, a frame
//! after `finish` is refused with `MonitorError::Finished`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use monitor_core::{json, Config, Monitor, MonitorError};

fuzz_target!(|data: &[u8]| {
    let mut monitor: Monitor = Monitor::new(Config::DEFAULT).expect("default config is valid");
    // The input is a sequence of frames separated by newlines (JSON lines, as `sds frames`
    // writes them); the whole input is also tried as one frame.
    let _ = json::decode_frame(data);
    for line in data.split(|&b| b == b'\n') {
        let Ok(frame) = json::decode_frame(line) else {
            continue;
        };
        let before = *monitor.summary();
        match monitor.push(&frame) {
            Ok(_) => assert_eq!(monitor.frames(), before.frames + 1),
            Err(_) => assert_eq!(
                *monitor.summary(),
                before,
                "a refused frame changed the state"
            ),
        }
    }
    let done = monitor.finish().expect("first finish succeeds");
    let frames = done.summary.frames;
    if let Some(c) = done.summary.comfort_score() {
        assert!((0.0..=1.0).contains(&c), "comfort {c} out of range");
    }
    assert!(done.summary.comfort.comfortable <= done.summary.comfort.chunks);
    assert!(done.summary.lateral.scored_chunks <= done.summary.lateral.chunks);
    // Frames and a second finish after the route ended are refused, not a panic.
    if let Ok(frame) = json::decode_frame(data) {
        assert_eq!(monitor.push(&frame).err(), Some(MonitorError::Finished));
    }
    assert_eq!(monitor.finish().err(), Some(MonitorError::Finished));
    assert_eq!(monitor.frames(), frames);
});
