//! `monitor_replay FRAMES.jsonl...`: the host's side of the firmware comparison (proof 1 of
//! `firmware-example/run-tests.sh`).
//!
//! Reads the frames `sds frames` wrote (one `monitor_core::Frame` per line, decoded with
//! `monitor_core::json::decode_frame`), runs them through `monitor_core::Monitor` with the
//! default configuration, and prints, exactly as the firmware does over semihosting, for each
//! file (one route each, a fresh monitor each):
//!
//! ```text
//! route I           the route's index, from 0, in the order of the arguments
//! event {json}      one line per event, in order (push events, then finish events)
//! summary {json}    the route summary
//! pins {json}       what the firmware's two output pins must have done
//! ```
//!
//! JSON is written with `monitor_core::json::encode`, the serializer the firmware uses. The
//! `pins` line is computed here independently from the events, with the rule the firmware's
//! README documents: the alarm pin latches high on a collision without deceleration or a
//! critical lateral chunk; the comfort pin is high while the last comfort chunk failed.

use std::io::{self, BufWriter, Write};
use std::process::ExitCode;

use monitor_core::{json, Band, Event, Monitor};

/// The pins' expected behaviour, derived from the events alone.
#[derive(Default)]
struct Pins {
    alarm: bool,
    alarm_rises: u32,
    comfort: bool,
    comfort_rises: u32,
}

impl Pins {
    fn see(&mut self, e: &Event) {
        let alarm = match e {
            Event::Collision(v) => v.nodecel(),
            Event::Lateral(v) => v.band == Band::Critical,
            Event::Comfort(v) => {
                let failed = !v.failed.comfortable();
                if failed && !self.comfort {
                    self.comfort_rises += 1;
                }
                self.comfort = failed;
                false
            }
        };
        if alarm && !self.alarm {
            self.alarm = true;
            self.alarm_rises += 1;
        }
    }
}

/// `prefix`, a space, the JSON `encode` writes into a 640-byte buffer (the firmware's), a newline.
fn line(
    out: &mut impl Write,
    prefix: &str,
    encode: impl FnOnce(&mut [u8]) -> Result<usize, json::JsonError>,
) -> Result<(), String> {
    let mut buf = [0u8; 640];
    let n = encode(&mut buf).map_err(|e| format!("encoding a {prefix} line: {e}"))?;
    let text = buf.get(..n).ok_or("encoder overran its buffer")?;
    out.write_all(prefix.as_bytes())
        .and_then(|()| out.write_all(b" "))
        .and_then(|()| out.write_all(text))
        .and_then(|()| out.write_all(b"\n"))
        .map_err(|e| format!("stdout: {e}"))
}

fn run(index: usize, path: &str, out: &mut impl Write) -> Result<(), String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{path}: {e}"))?;
    let mut monitor: Monitor = Monitor::default();
    let mut pins = Pins::default();
    writeln!(out, "route {index}").map_err(|e| format!("stdout: {e}"))?;
    for (i, raw) in text.lines().enumerate() {
        let raw = raw.trim();
        if raw.is_empty() {
            continue;
        }
        let frame = json::decode_frame(raw.as_bytes())
            .map_err(|e| format!("{path} line {}: {e}", i + 1))?;
        let events = monitor
            .push(&frame)
            .map_err(|e| format!("{path} line {}: {e}", i + 1))?;
        for e in &events {
            pins.see(e);
            line(out, "event", |b| json::encode(e, b))?;
        }
    }
    let done = monitor.finish().map_err(|e| format!("{path}: {e}"))?;
    for e in &done.events {
        pins.see(e);
        line(out, "event", |b| json::encode(e, b))?;
    }
    line(out, "summary", |b| json::encode(&done.summary, b))?;
    writeln!(
        out,
        "pins {{\"alarm\":{},\"alarm_rises\":{},\"comfort\":{},\"comfort_rises\":{}}}",
        pins.alarm, pins.alarm_rises, pins.comfort, pins.comfort_rises
    )
    .map_err(|e| format!("stdout: {e}"))
}

fn main() -> ExitCode {
    let paths: Vec<String> = std::env::args().skip(1).collect();
    if paths.is_empty() {
        eprintln!("usage: monitor_replay FRAMES.jsonl...   (one route per file, as `sds frames` writes them)");
        return ExitCode::from(2);
    }
    let stdout = io::stdout();
    let mut out = BufWriter::new(stdout.lock());
    let result = paths
        .iter()
        .enumerate()
        .try_for_each(|(i, p)| run(i, p, &mut out))
        .and_then(|()| out.flush().map_err(|e| format!("stdout: {e}")));
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("monitor_replay: {e}");
            ExitCode::FAILURE
        }
    }
}
