//! Our side of the CARLA cross-check (`scripts/map-crosscheck.sh`).
//!
//! `map_project MAP.xodr sample N SEED`: N seeded points within 6 m of a driving lane's centre
//! line (CARLA x y z, one per line), lanes drawn by length so junctions are included.
//!
//! `map_project MAP.xodr project`: reads `x y z` lines, prints per point
//! `road lane s width distance_2d distance_3d junction foot_x foot_y second` where `second` is
//! the 3-D distance of the nearest *other* lane (other road or lane id) if it lies within 5 cm
//! of the nearest, else `inf`, then the nearest distance over all lanes and the lane section index.
use std::io::{BufRead, Write};

use monitor_host::geometry::map::Map;

/// splitmix64: a tiny, well-known seeded generator (no dependency needed).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    fn uniform(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if args.len() < 3 {
        eprintln!("usage: map_project MAP.xodr sample N SEED | project");
        std::process::exit(2);
    }
    let t = std::time::Instant::now();
    let map = Map::load(std::path::Path::new(&args[1])).unwrap_or_else(|e| {
        eprintln!("{e}");
        std::process::exit(1)
    });
    eprintln!(
        "loaded {} in {:.1} ms: {} lanes",
        args[1],
        t.elapsed().as_secs_f64() * 1e3,
        map.lane_count()
    );
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    match args[2].as_str() {
        "sample" => {
            let n: usize = args.get(3).and_then(|a| a.parse().ok()).unwrap_or(1000);
            let seed: u64 = args.get(4).and_then(|a| a.parse().ok()).unwrap_or(1);
            let lanes = map.lanes();
            let total: f64 = lanes.iter().map(|l| l.length).sum();
            let mut rng = Rng(seed);
            for _ in 0..n {
                let mut pick = rng.uniform() * total;
                let lane = lanes
                    .iter()
                    .find(|l| {
                        pick -= l.length;
                        pick < 0.0
                    })
                    .unwrap_or(&lanes[lanes.len() - 1]);
                let s = lane.s0 + rng.uniform() * (lane.s1 - lane.s0);
                let h = 1e-3;
                let (Some(c), Some(a), Some(b)) = (
                    map.lane_point(&lane.lane, s),
                    map.lane_point(&lane.lane, (s - h).max(lane.s0)),
                    map.lane_point(&lane.lane, (s + h).min(lane.s1)),
                ) else {
                    continue;
                };
                let (tx, ty) = (b[0] - a[0], b[1] - a[1]);
                let norm = tx.hypot(ty).max(1e-12);
                let off = (rng.uniform() * 2.0 - 1.0) * 6.0;
                let x = c[0] - ty / norm * off;
                let y = c[1] + tx / norm * off;
                let z = c[2] + rng.uniform() * 0.5;
                writeln!(out, "{x:.6} {y:.6} {z:.6}").unwrap();
            }
        }
        "project" => {
            let stdin = std::io::stdin();
            for line in stdin.lock().lines() {
                let line = line.unwrap();
                let v: Vec<f64> = line
                    .split_whitespace()
                    .filter_map(|w| w.parse().ok())
                    .collect();
                if v.len() < 3 {
                    continue;
                }
                let all = map.project_within(v[0], v[1], v[2], 0.05);
                let Some(best) = map.project(v[0], v[1], v[2]) else {
                    writeln!(out, "none").unwrap();
                    continue;
                };
                let rid = map.road_id(best.lane.road);
                let second = all
                    .iter()
                    .filter(|p| map.road_id(p.lane.road) != rid || p.lane.lane != best.lane.lane)
                    .map(|p| p.distance_3d)
                    .fold(f64::INFINITY, f64::min);
                writeln!(
                    out,
                    "{} {} {:.9} {:.9} {:.9} {:.9} {} {:.9} {:.9} {:.9} {} {}",
                    rid,
                    best.lane.lane,
                    best.s,
                    best.width,
                    best.distance_2d,
                    best.distance_3d,
                    u8::from(best.junction),
                    best.foot[0],
                    best.foot[1],
                    second,
                    all.first().map_or(best.distance_3d, |p| p.distance_3d),
                    best.lane.section,
                )
                .unwrap();
            }
        }
        "point" => {
            // Debugging aid: `point ROAD LANE S...`: lane centre points (CARLA x y z).
            let lane: i32 = args[4].parse().unwrap_or(0);
            for a in &args[5..] {
                let s: f64 = a.parse().unwrap_or(0.0);
                let r = map.lane_at(&args[3], lane, s);
                let p = r.and_then(|r| map.lane_point(&r, s));
                writeln!(out, "s {s} {r:?} {p:?}").unwrap();
            }
        }
        "within" => {
            // Debugging aid: every lane within MARGIN (default 0.5 m) of the nearest.
            let margin: f64 = args.get(3).and_then(|a| a.parse().ok()).unwrap_or(0.5);
            let stdin = std::io::stdin();
            for line in stdin.lock().lines() {
                let line = line.unwrap();
                let v: Vec<f64> = line
                    .split_whitespace()
                    .filter_map(|w| w.parse().ok())
                    .collect();
                if v.len() < 3 {
                    continue;
                }
                writeln!(out, "point {} {} {}", v[0], v[1], v[2]).unwrap();
                for p in map.project_within(v[0], v[1], v[2], margin) {
                    writeln!(
                        out,
                        "  road {} section {} lane {} s {:.6} d3 {:.6} d2 {:.6} foot {:.4} {:.4} {:.4}",
                        map.road_id(p.lane.road),
                        p.lane.section,
                        p.lane.lane,
                        p.s,
                        p.distance_3d,
                        p.distance_2d,
                        p.foot[0],
                        p.foot[1],
                        p.foot_z
                    )
                    .unwrap();
                }
            }
        }
        other => {
            eprintln!("unknown mode {other}");
            std::process::exit(2);
        }
    }
}
