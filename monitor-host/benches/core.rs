//! Criterion benchmarks of the streaming core on the host (`cargo bench --bench core`).
//!
//! - `core/push_amortised`: a 4,000-frame route pushed into a fresh monitor (time per frame is
//!   the reported time / 4,000; criterion prints it as a throughput in elements/s).
//! - `core/push_chunk_end`: the 20th frame of a chunk, where the chunk is filtered and scored
//!   (the worst frame).
//! - `core/push_mid_chunk`: an ordinary frame (the 11th of a chunk).

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, BatchSize, Criterion, Throughput};
use monitor_core::{Config, Frame, Monitor};

#[path = "common/frames.rs"]
mod frames;

const ROUTE: usize = 4000;

fn route(table: &[Frame]) -> u32 {
    let mut m: Monitor = Monitor::new(Config::DEFAULT).expect("default config is valid");
    for i in 0..ROUTE {
        let events = m
            .push(black_box(&table[i % table.len()]))
            .expect("valid frame");
        black_box(events);
    }
    m.frames()
}

/// A monitor that has consumed `n` frames of the table.
fn after(table: &[Frame], n: usize) -> Monitor {
    let mut m: Monitor = Monitor::new(Config::DEFAULT).expect("default config is valid");
    for f in &table[..n] {
        m.push(f).expect("valid frame");
    }
    m
}

fn bench(c: &mut Criterion) {
    let table = frames::table();
    let mut g = c.benchmark_group("core");
    g.throughput(Throughput::Elements(ROUTE as u64));
    g.bench_function("push_amortised", |b| b.iter(|| route(&table)));
    g.throughput(Throughput::Elements(1));
    for (name, before) in [("push_chunk_end", 19), ("push_mid_chunk", 10)] {
        let start = after(&table, before);
        let frame = table[before];
        g.bench_function(name, |b| {
            b.iter_batched_ref(
                || start.clone(),
                |m| black_box(m.push(black_box(&frame)).expect("valid frame")),
                BatchSize::SmallInput,
            )
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
