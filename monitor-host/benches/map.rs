//! Criterion benchmarks of the OpenDRIVE map (`cargo bench -p monitor-host --bench map`), on
//! the CARLA towns in `../shared/fixtures/maps` (skipped, with a message, when absent):
//!
//! - `map/load/Town04`: read and build Town04 (3.4 MB): XML, geometry, lane network, index;
//! - `map/project_frame/history`: the lateral reference of one frame with a map: the exact
//!   projection of consecutive frames of a drive along the bench2drive220 Town04 routes, each
//!   search starting from the previous frame's lane piece ([`Projector`]); criterion's
//!   throughput is frames/s;
//! - `map/project_frame/plain`: the same frames through `Map::project` (no history);
//! - `map/dense_route/Town04`: the dense route (with junction gaps filled) of every Town04 route.
//!
//! Each is measured twice: `map/*` in wall time, `map_cpu/*` in this thread's CPU time (on a
//! shared machine, time while another process holds the core is not counted).

use std::hint::black_box;
use std::path::{Path, PathBuf};

use std::time::Duration;

use criterion::{criterion_group, criterion_main, Bencher, Criterion, Throughput};
use monitor_host::geometry::map::{dense_route, Map, Projector};
use monitor_host::input::route_xml;

#[path = "common/cpu.rs"]
mod cpu;

/// Runs `f` as a criterion routine, timed by wall clock or by this thread's CPU clock.
fn run<T>(b: &mut Bencher, cpu_time: bool, mut f: impl FnMut() -> T) {
    if !cpu_time {
        return b.iter(&mut f);
    }
    b.iter_custom(|iters| {
        let wall = std::time::Instant::now();
        let start = cpu::thread_cpu_ns();
        for _ in 0..iters {
            black_box(f());
        }
        match (start, cpu::thread_cpu_ns()) {
            (Some(a), Some(b)) => Duration::from_nanos(b - a),
            _ => wall.elapsed(),
        }
    })
}

fn shared() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/fixtures")
}

/// Waypoints (z = 0, as the route XML reader keeps them) of every Town04 route.
fn town04_routes() -> Vec<Vec<[f64; 3]>> {
    let Ok(set) = route_xml::read_route_xml(&shared().join("b2d/routes/bench2drive220.xml")) else {
        return Vec::new();
    };
    set.iter()
        .filter(|r| r.town == "Town04")
        .map(|r| r.waypoints.iter().map(|w| [w[0], w[1], 0.0]).collect())
        .collect()
}

fn bench(c: &mut Criterion) {
    let path = shared().join("maps/Town04.xodr");
    if !path.is_file() {
        eprintln!("SKIP map benches: {} not found", path.display());
        return;
    }
    let map = Map::load(&path).unwrap();
    let routes = town04_routes();
    // A drive: the dense route's 1 m samples (one frame per metre: 20 m/s at 20 Hz), wobbling
    // up to 0.6 m sideways, at the height of the road found below.
    let mut frames = Vec::new();
    for r in &routes {
        for (i, s) in dense_route(r, 8.0, Some(&map)).iter().enumerate() {
            let w = 0.6 * (i as f64 * 0.37).sin();
            let z = map.project(s.xy[0], s.xy[1], 0.0).map_or(0.0, |p| p.foot_z);
            frames.push([s.xy[0] + w * 0.3, s.xy[1] + w, z]);
        }
    }
    eprintln!("{} Town04 routes, {} frames", routes.len(), frames.len());
    for (group, cpu_time) in [("map", false), ("map_cpu", true)] {
        let mut g = c.benchmark_group(group);
        g.sample_size(20);
        g.bench_function("load/Town04", |b| {
            run(b, cpu_time, || Map::load(black_box(&path)).unwrap())
        });
        if !frames.is_empty() {
            g.throughput(Throughput::Elements(frames.len() as u64));
            g.bench_function("project_frame/history", |b| {
                run(b, cpu_time, || {
                    let mut p = Projector::new(&map);
                    let mut sum = 0.0;
                    for f in &frames {
                        sum += p.project(f[0], f[1], f[2]).map_or(0.0, |x| x.distance_2d);
                    }
                    sum
                })
            });
            g.bench_function("project_frame/plain", |b| {
                run(b, cpu_time, || {
                    let mut sum = 0.0;
                    for f in &frames {
                        sum += map.project(f[0], f[1], f[2]).map_or(0.0, |x| x.distance_2d);
                    }
                    sum
                })
            });
            g.throughput(Throughput::Elements(routes.len() as u64));
            g.bench_function("dense_route/Town04", |b| {
                run(b, cpu_time, || {
                    routes
                        .iter()
                        .map(|r| dense_route(r, 8.0, Some(&map)).len())
                        .sum::<usize>()
                })
            });
        }
        g.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
