//! The MCAP reader (`monitor_host::input::mcap`) on arbitrary bytes: the streamed records
//! (`stream::stream_from`) never panic and never hold more than a record's bound, and a log read
//! from a file (`read_log`, 20 Hz, the default topics and hold) gives frames or an error naming
//! the file. Seeds (fuzz/seeds.py): a small valid log, a chunk ending mid-record, a chunk of
//! zeros, a chunk whose CRC does not hold, the magic then zeros, a stray time stamp, poses at
//! one time (issue 47 findings 5, 9, 10).
#![no_main]

use libfuzzer_sys::fuzz_target;
use monitor_host::input::mcap::{read_log, stream, Topics};

fuzz_target!(|data: &[u8]| {
    let mut seen = 0u64;
    if let Ok(s) = stream::stream_from(data, data.len() as u64, &|_| true, |m| {
        seen += 1;
        assert!(m.data.len() <= stream::RECORD_LIMIT);
        Ok(())
    }) {
        // Every message delivered was counted on its topic.
        assert!(s.messages >= seen, "{} counted, {seen} delivered", s.messages);
    }
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("drive.mcap");
    std::fs::write(&path, data).expect("write");
    match read_log(&path, &Topics::default(), 0.05, 0.25) {
        Ok(log) => {
            let n = log.telemetry.frames.len();
            assert_eq!(log.times.len(), n);
            assert!(log.telemetry.segments.iter().all(|&s| s < n));
            assert!(log.telemetry.segments.windows(2).all(|w| w[0] < w[1]));
        }
        Err(e) => {
            let msg = e.to_string();
            assert!(msg.contains("drive.mcap"), "error does not name the file: {msg}");
        }
    }
});
