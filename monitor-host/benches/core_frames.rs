//! Instruction counts of the core under callgrind (`harness = false`): pushes N frames into a
//! fresh monitor inside `push_frames`, which `bench/run.sh` collects alone with
//! `valgrind --tool=callgrind --toggle-collect='*push_frames*'`.
//!
//! Usage: `core_frames N`. Instructions per frame, amortised:
//! `(I(40000) - I(20000)) / 20000`; the chunk-end (20th) frame: `I(20) - I(19)`; an ordinary
//! frame: `I(19) - I(18)`. `finish` is not called, so each difference is pushes only.

use std::hint::black_box;

use monitor_core::{Config, Frame, Monitor};

#[path = "common/frames.rs"]
mod frames;

#[inline(never)]
fn push_frames(m: &mut Monitor, table: &[Frame], n: usize) {
    let mut k = 0;
    for _ in 0..n {
        let events = m.push(&table[k]).expect("valid frame");
        black_box(events);
        k += 1;
        if k == table.len() {
            k = 0;
        }
    }
}

fn main() {
    // `cargo bench` passes `--bench`; only a bare number is ours.
    let n = std::env::args()
        .skip(1)
        .find_map(|a| a.parse::<usize>().ok())
        .unwrap_or(20_000);
    let table = frames::table();
    let mut m: Monitor = Monitor::new(Config::DEFAULT).expect("default config is valid");
    push_frames(&mut m, black_box(&table), black_box(n));
    black_box(&m);
}
