//! Writes a long vehicle log for the memory benchmark (`bench/drive-memory.sh`, issue 51 goal 2):
//! `cargo run --release -p monitor-host --example write_drive -- OUT.mcap SECONDS`.
//!
//! A drive at 20 Hz along a gentle weave (odometry and IMU, the library's writer:
//! `monitor_host::demo::drive`, zstd chunks), an event on `/events` every ten minutes and a
//! short recorder pause every half hour (a gap: a new segment). The writer holds one chunk at a
//! time, so an 8-hour log is written in bounded memory.

use monitor_host::demo::drive::{write_weave, LogOptions, Weave};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let [_, out, seconds] = &args[..] else {
        return Err("usage: write_drive OUT.mcap SECONDS".into());
    };
    let weave = Weave {
        seconds: seconds.parse()?,
        pause_every: 1_800,
        event_every: 600,
        log: LogOptions {
            chunk_size: 1 << 20,
            zstd: true,
            ..LogOptions::default()
        },
    };
    write_weave(std::path::Path::new(out), &weave)?;
    Ok(())
}
