//! Where the host replay's time goes, stage by stage, single thread (`harness = false`).
//!
//! Usage: `replay_stages RUN_DIR [MAX_ROUTES]`, where `RUN_DIR` is what `sds demo --large`
//! wrote (`results.json`, `telemetry/`, `routes.xml`). For every route, in turn:
//!
//! | stage     | what is timed                                                             |
//! |-----------|---------------------------------------------------------------------------|
//! | `read`    | `std::fs::read` of `metric_info.json` (page cache)                        |
//! | `skip`    | `serde_json` over the same bytes into `IgnoredAny`: the parser's own floor |
//! | `reader`  | `serde_json::from_reader` (64 KB `BufReader`) into `IgnoredAny`: the     |
//! |           | floor of a parse that never holds the whole file                          |
//! | `dom`     | `serde_json::Value` of the same bytes (first 20 routes only): a DOM's cost |
//! | `parse`   | `metric_info::parse_metric_info` (the scanner; serde visitor on doubt)     |
//! | `serde`   | `metric_info::parse_metric_info_serde` (the serde_json visitor alone)       |
//! | `prepare` | `prepare::prepare`: speeds, lateral error, alignment, `Frame`s              |
//! | `stream`  | `replay::stream`: the monitor over every frame (Bench2Drive's smoothness, |
//! |           | docs/SCORE.md §10.1, counted beside the run's comfort, as `replay` does)                  |
//! | `batch`   | `batch::compute_with`: the batch reference check on the same frames       |
//! | `replay`  | `replay::replay`: the whole per-route pipeline (locate, read ... score)    |
//! | `motion`  | `motion::measure` (docs/SCORE.md §10.0 distance, stationary share, moving chunks), with    |
//! |           | the locations and steps it is given (inside `prepare` they exist already)  |
//!
//! With `SDS_PARSE_PASSES=N` in the environment it only parses the run's files (read once,
//! held) N times and prints the fastest pass (`stage=parse-passes ... mb_s=`): steadier than
//! one pass for comparing parser changes.
//!
//! Prints one line per stage: `stage=NAME routes=R frames=F bytes=B wall_s=W cpu_s=C`, where
//! `cpu_s` is this thread's CPU time (`CLOCK_THREAD_CPUTIME_ID`; equal to `wall_s` where that
//! clock is missing), which other processes on a shared machine do not inflate.

use std::hint::black_box;
use std::path::PathBuf;
use std::time::Instant;

use monitor_host::input::{metric_info, results_file, route_xml};
use monitor_host::pipeline::{motion, prepare, replay};
use monitor_host::reference::batch;
use monitor_host::Settings;

#[path = "common/cpu.rs"]
mod cpu;

/// This thread's CPU time in seconds, if the kernel tells.
fn thread_cpu() -> Option<f64> {
    cpu::thread_cpu_ns().map(|ns| ns as f64 * 1e-9)
}

#[derive(Default, Clone, Copy)]
struct Acc {
    routes: u64,
    frames: u64,
    bytes: u64,
    wall: f64,
    cpu: f64,
}

/// Times `f`, adding to `acc`.
fn timed<T>(acc: &mut Acc, frames: usize, bytes: usize, f: impl FnOnce() -> T) -> T {
    let c0 = thread_cpu();
    let t0 = Instant::now();
    let out = f();
    let wall = t0.elapsed().as_secs_f64();
    let cpu = match (c0, thread_cpu()) {
        (Some(a), Some(b)) => b - a,
        _ => wall,
    };
    acc.routes += 1;
    acc.frames += frames as u64;
    acc.bytes += bytes as u64;
    acc.wall += wall;
    acc.cpu += cpu;
    out
}

/// The fastest of `passes` parses of the run's `metric_info.json` files (held in memory).
fn parse_passes(dir: &std::path::Path, max: usize, passes: usize) -> anyhow::Result<()> {
    let mut files = Vec::new();
    for entry in std::fs::read_dir(dir.join("telemetry"))?.take(max) {
        files.push(std::fs::read(entry?.path().join("metric_info.json"))?);
    }
    let bytes: usize = files.iter().map(Vec::len).sum();
    let mut best = f64::MAX;
    for _ in 0..passes {
        let mut acc = Acc::default();
        for f in &files {
            let t = timed(&mut acc, 0, f.len(), || {
                metric_info::parse_metric_info(black_box(f))
            })?;
            drop(black_box(t));
        }
        best = best.min(acc.cpu);
    }
    println!(
        "stage=parse-passes files={} bytes={bytes} passes={passes} best_cpu_s={best:.6} mb_s={:.0}",
        files.len(),
        bytes as f64 / best / 1e6
    );
    Ok(())
}

fn main() -> anyhow::Result<()> {
    // `cargo bench` passes `--bench`; the rest are ours.
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--"))
        .collect();
    let dir = PathBuf::from(
        args.first()
            .map_or("target/bench-run/large", String::as_str),
    );
    let max: usize = args
        .get(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(usize::MAX);

    // `SDS_PARSE_PASSES=N`: only the parse, N passes over the run's files (each read once,
    // held), printing the fastest pass: a steadier figure for comparing parser changes.
    if let Some(passes) = std::env::var("SDS_PARSE_PASSES")
        .ok()
        .and_then(|v| v.parse::<usize>().ok())
    {
        return parse_passes(&dir, max, passes);
    }
    let set = results_file::read_results(&dir.join("results.json"))?;
    let routes = route_xml::read_route_xml(&dir.join("routes.xml"))?;
    let settings = Settings::default();
    let telemetry_root = dir.join("telemetry");
    let names = [
        "read", "skip", "dom", "parse", "prepare", "stream", "batch", "replay", "reader", "serde",
        "motion",
    ];
    let mut acc = [Acc::default(); 11];
    let mut agree = true;
    for (k, loaded) in set.records.iter().take(max).enumerate() {
        let record = loaded.entry.as_ref().map_err(|e| anyhow::anyhow!("{e}"))?;
        let save = record.save_name.as_deref().unwrap_or_default();
        let file = telemetry_root.join(save).join("metric_info.json");

        let bytes = timed(&mut acc[0], 0, 0, || std::fs::read(&file))?;
        let n = bytes.len();
        timed(&mut acc[1], 0, n, || {
            serde_json::from_slice::<serde::de::IgnoredAny>(black_box(&bytes))
        })?;
        timed(&mut acc[8], 0, n, || {
            let f = std::io::BufReader::with_capacity(1 << 16, std::fs::File::open(&file)?);
            serde_json::from_reader::<_, serde::de::IgnoredAny>(f).map_err(anyhow::Error::from)
        })?;
        if k < 20 {
            let v = timed(&mut acc[2], 0, n, || {
                serde_json::from_slice::<serde_json::Value>(black_box(&bytes))
            })?;
            drop(black_box(v));
        }
        let tel = timed(&mut acc[3], 0, n, || {
            metric_info::parse_metric_info(black_box(&bytes))
        })?;
        let by_serde = timed(&mut acc[9], 0, n, || {
            metric_info::parse_metric_info_serde(black_box(&bytes))
        })?;
        agree &= by_serde == tel;
        drop(by_serde);
        let frames = tel.frames.len();
        acc[0].frames += frames as u64;
        acc[0].bytes += n as u64;
        acc[1].frames += frames as u64;
        if k < 20 {
            acc[2].frames += frames as u64;
        }
        acc[3].frames += frames as u64;
        acc[8].frames += frames as u64;
        acc[9].frames += frames as u64;
        timed(&mut acc[10], frames, n, || {
            black_box(motion::measure(
                &tel.locations(),
                &tel.steps(),
                0.05,
                &settings.motion,
                usize::from(settings.core.chunk_len),
                usize::from(settings.core.min_chunk),
            ))
        });
        let mut prepared = timed(&mut acc[4], frames, n, || {
            prepare::prepare(record, &tel, Some(&routes), None, None, &settings)
        });
        let summary = timed(&mut acc[5], frames, n, || {
            replay::stream(&mut prepared, &settings.core)
        })
        .map_err(|e| anyhow::anyhow!("frame {}: {e}", e.index()))?;
        let reference = timed(&mut acc[6], frames, n, || {
            let core = &settings.core;
            batch::compute_with(&prepared.frames, core, replay::smoothness_profile(core))
        });
        agree &= reference.summary == summary;
        let out = timed(&mut acc[7], frames, n, || {
            replay::replay(
                loaded,
                Some(&routes),
                None,
                Some(&telemetry_root),
                &settings,
            )
        });
        agree &= out.batch_agrees == Some(true);
        drop((bytes, tel, prepared));
    }
    for (name, a) in names.iter().zip(acc) {
        println!(
            "stage={name} routes={} frames={} bytes={} wall_s={:.6} cpu_s={:.6}",
            a.routes, a.frames, a.bytes, a.wall, a.cpu
        );
    }
    if !agree {
        anyhow::bail!("the batch reference disagreed with the stream, or the parse paths differ");
    }
    Ok(())
}
