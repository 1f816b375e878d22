//! Criterion benchmarks of the streaming core on the host (`cargo bench --bench core`).
//!
//! - `core/push_amortised`: a 4,000-frame route pushed into a fresh monitor (time per frame is
//!   the reported time / 4,000; criterion prints it as a throughput in elements/s).
//! - `core/push_chunk_end`: the 20th frame of a chunk, where the chunk is filtered and scored
//!   (the worst frame).
//! - `core/push_mid_chunk`: an ordinary frame (the 11th of a chunk).
//!
//! Each is measured twice: `core/*` in wall time, `core_cpu/*` in this thread's CPU time (what
//! `bench/run.sh` compares with the goal on a shared machine).

use std::hint::black_box;

use criterion::measurement::{Measurement, ValueFormatter, WallTime};
use criterion::{criterion_group, criterion_main, BatchSize, Criterion, Throughput};
use monitor_core::{Config, Frame, Monitor};

#[path = "common/cpu.rs"]
mod cpu;
#[path = "common/frames.rs"]
mod frames;

/// Criterion measurement of this thread's CPU time, in ns (wall time where the clock is
/// missing): on a shared machine, time while another process holds the core is not counted.
struct CpuTime;

fn now_ns() -> u64 {
    cpu::thread_cpu_ns().unwrap_or_else(|| {
        std::time::UNIX_EPOCH
            .elapsed()
            .map_or(0, |d| d.as_nanos() as u64)
    })
}

impl Measurement for CpuTime {
    type Intermediate = u64;
    type Value = std::time::Duration;

    fn start(&self) -> u64 {
        now_ns()
    }
    fn end(&self, i: u64) -> std::time::Duration {
        std::time::Duration::from_nanos(now_ns().saturating_sub(i))
    }
    fn add(&self, a: &Self::Value, b: &Self::Value) -> Self::Value {
        *a + *b
    }
    fn zero(&self) -> Self::Value {
        std::time::Duration::ZERO
    }
    fn to_f64(&self, v: &Self::Value) -> f64 {
        v.as_nanos() as f64
    }
    fn formatter(&self) -> &dyn ValueFormatter {
        static WALL: WallTime = WallTime;
        WALL.formatter()
    }
}

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

fn bench<M: Measurement>(c: &mut Criterion<M>, group: &str) {
    let table = frames::table();
    let mut g = c.benchmark_group(group);
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

fn wall(c: &mut Criterion) {
    bench(c, "core");
}

fn cpu(c: &mut Criterion<CpuTime>) {
    bench(c, "core_cpu");
}

criterion_group!(wall_time, wall);
criterion_group! {
    name = cpu_time;
    config = Criterion::default().with_measurement(CpuTime);
    targets = cpu
}
criterion_main!(wall_time, cpu_time);
