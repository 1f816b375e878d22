//! `sds demo`: a small synthetic Bench2Drive run of the project's own making.
//!
//! It writes what a real run leaves behind: a raw evaluator results file, one Bench2Drive
//! `metric_info.json` per route under `telemetry/<save_name>/`, a route XML, and the OpenDRIVE
//! map of its town (`maps/DemoTown.xodr`, a road through a junction). The routes are straight
//! roads driven with simple kinematics, chosen so that every SDS term shows up once: cruising,
//! hard braking, a lane change, a cone contact, collisions with and without braking, a hit while
//! standing still (then blocked), a route whose agent writes telemetry at 10 Hz (one step per
//! 0.1 s, as real published `metric_info.json` files do), and a drift inside a junction that the
//! route XML leaves out and only the map lets the score see, on a route that also runs the
//! junction's red light. `--large` writes a benchmark-sized run (220 routes x 4,000
//! frames) of cruising routes for performance measurements.

use std::fmt::Write as _;
use std::fs;
use std::path::{Path, PathBuf};

pub mod drive;
mod frame;
mod map;
mod telemetry;

pub use map::TOWN;

pub use frame::LargeLayout;
use frame::SimFrame;
use telemetry::{write_metric_info, write_metric_info_realistic};

/// Why the demo run could not be written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DemoError {
    /// A file or folder could not be written.
    #[error("{what}: {source}")]
    Write {
        /// What was being written (naming the file or route).
        what: String,
        /// The OS error.
        #[source]
        source: std::io::Error,
    },
}

type Result<T> = std::result::Result<T, DemoError>;

/// Names the file an I/O error concerns.
fn at(what: impl std::fmt::Display) -> impl FnOnce(std::io::Error) -> DemoError {
    move |source| DemoError::Write {
        what: what.to_string(),
        source,
    }
}

/// Step period of the simulator (20 Hz).
const DT: f64 = 0.05;
/// Step period of an agent that writes telemetry every other tick (10 Hz).
const DT_10HZ: f64 = 0.1;
/// World origin of every demo road: large coordinates, as on real CARLA maps.
const ORIGIN: [f64; 2] = [1520.0, -3310.0];

/// What happens in one demo route.
#[derive(Clone, Debug)]
struct Script {
    name: &'static str,
    xml_id: u32,
    frames: usize,
    /// Seconds per telemetry step.
    dt: f64,
    v0: f64,
    /// Longitudinal acceleration command at frame i.
    accel: fn(usize) -> f64,
    /// Lateral offset from the reference line at time t (s), and its second derivative.
    lateral: fn(f64) -> (f64, f64),
    /// Collisions: (frame, list, type_id).
    collisions: &'static [(usize, &'static str, &'static str)],
    /// The evaluator's other infractions.
    others: &'static [Other],
    status: &'static str,
    score_route: f64,
    /// The route XML leaves out its waypoints strictly between these (m from the origin), as
    /// real route files leave out junctions.
    xml_gap: Option<(f64, f64)>,
}

/// An infraction other than a collision, with the position CARLA's criteria write into it.
#[derive(Clone, Copy, Debug)]
enum Other {
    /// A red light run; the light stands `side` m beside the road, `at` m along it (the
    /// message carries the light's position, not the ego's).
    RedLight { at: f64, side: f64 },
    /// The agent got blocked: the message carries the ego's position at the last frame.
    Blocked,
}

fn straight(_: f64) -> (f64, f64) {
    (0.0, 0.0)
}

/// A 3.5 m minimum-jerk lane change to the right between t = 2 s and t = 6 s:
/// `y = w (10s³ - 15s⁴ + 6s⁵)`, `s = (t - 2) / 4`; lateral acceleration at most 1.26 m/s²,
/// lateral jerk at most 3.28 m/s³.
fn lane_change(t: f64) -> (f64, f64) {
    let (t0, dur, width) = (2.0, 4.0, 3.5);
    let s = (t - t0) / dur;
    if s <= 0.0 {
        return (0.0, 0.0);
    }
    if s >= 1.0 {
        return (width, 0.0);
    }
    let (s2, s3) = (s * s, s * s * s);
    (
        width * (10.0 * s3 - 15.0 * s2 * s2 + 6.0 * s3 * s2),
        width * (60.0 * s - 180.0 * s2 + 120.0 * s3) / (dur * dur),
    )
}

/// A 1.4 m drift to the right and back between t = 4 s and t = 8.5 s (48-102 m at 12 m/s),
/// smooth enough to stay comfortable: `y = A sin⁴(π s)`, `s = (t - 4) / 4.5`; lateral
/// acceleration at most 2.73 m/s², and zero at both ends.
fn junction_drift(t: f64) -> (f64, f64) {
    let (t0, dur, a) = (4.0, 4.5, 1.4);
    let s = (t - t0) / dur;
    if !(0.0..=1.0).contains(&s) {
        return (0.0, 0.0);
    }
    let w = std::f64::consts::PI;
    let (sn, cs) = ((w * s).sin(), (w * s).cos());
    (
        a * sn.powi(4),
        a * 4.0 * w * w * (3.0 * sn * sn * cs * cs - sn.powi(4)) / (dur * dur),
    )
}

fn scripts() -> Vec<Script> {
    vec![
        Script {
            name: "DemoCruising_1",
            xml_id: 900001,
            frames: 200,
            dt: DT,
            v0: 10.0,
            accel: |_| 0.0,
            lateral: straight,
            collisions: &[],
            others: &[],
            status: "Completed",
            score_route: 100.0,
            xml_gap: None,
        },
        Script {
            name: "DemoHardBraking_1",
            xml_id: 900002,
            frames: 200,
            dt: DT,
            v0: 12.0,
            // Full braking at -6 m/s² from frame 60 until standstill.
            accel: |i| if (60..100).contains(&i) { -6.0 } else { 0.0 },
            lateral: straight,
            collisions: &[],
            others: &[],
            status: "Completed",
            score_route: 100.0,
            xml_gap: None,
        },
        Script {
            name: "DemoLaneChange_1",
            xml_id: 900003,
            frames: 200,
            dt: DT,
            v0: 10.0,
            accel: |_| 0.0,
            lateral: lane_change,
            collisions: &[],
            others: &[],
            status: "Completed",
            score_route: 100.0,
            xml_gap: None,
        },
        Script {
            name: "DemoConeContact_1",
            xml_id: 900004,
            frames: 160,
            dt: DT,
            v0: 3.0,
            accel: |_| 0.0,
            lateral: straight,
            collisions: &[(90, "collisions_layout", "static.prop.constructioncone")],
            others: &[],
            status: "Completed",
            score_route: 100.0,
            xml_gap: None,
        },
        Script {
            name: "DemoCrashNoBrake_1",
            xml_id: 900005,
            frames: 160,
            dt: DT,
            v0: 8.0,
            // The impact stops the car within 0.4 s.
            accel: |i| if (120..128).contains(&i) { -20.0 } else { 0.0 },
            lateral: straight,
            collisions: &[(120, "collisions_vehicle", "vehicle.lincoln.mkz_2020")],
            others: &[Other::Blocked],
            status: "Failed - Agent got blocked",
            score_route: 62.5,
            xml_gap: None,
        },
        Script {
            name: "DemoCrashBraking_1",
            xml_id: 900006,
            frames: 160,
            dt: DT,
            v0: 8.0,
            // Brakes at -3 m/s² from frame 100, too late: hits a pedestrian at frame 110.
            accel: |i| if (100..125).contains(&i) { -3.0 } else { 0.0 },
            lateral: straight,
            collisions: &[(110, "collisions_pedestrian", "walker.pedestrian.0012")],
            others: &[],
            status: "Completed",
            score_route: 100.0,
            xml_gap: None,
        },
        Script {
            name: "DemoStandingHit_1",
            xml_id: 900007,
            frames: 160,
            dt: DT,
            v0: 5.0,
            // Stops by frame 45 (-2.5 m/s² for 2 s) and is hit from behind while standing.
            accel: |i| if (5..45).contains(&i) { -2.5 } else { 0.0 },
            lateral: straight,
            collisions: &[(130, "collisions_vehicle", "vehicle.audi.tt")],
            others: &[],
            status: "Completed",
            score_route: 100.0,
            xml_gap: None,
        },
        Script {
            name: "Demo10HzBraking_1",
            xml_id: 900008,
            // 10 s at 10 Hz: the step period is inferred from duration_game (10.0 s / 100 steps).
            frames: 100,
            dt: DT_10HZ,
            v0: 10.0,
            // Brakes at -4 m/s² from t = 4.0 s and touches a car at t = 5.5 s, at 4 m/s.
            accel: |i| if (40..55).contains(&i) { -4.0 } else { 0.0 },
            lateral: straight,
            collisions: &[(55, "collisions_vehicle", "vehicle.tesla.model3")],
            others: &[],
            status: "Completed",
            score_route: 100.0,
            xml_gap: None,
        },
        Script {
            name: "DemoJunction_1",
            xml_id: 900009,
            // 10 s at 12 m/s, straight through the junction (60-90 m), drifting 1.4 m right
            // inside it. The route XML leaves out 56-94 m: only the map sees the drift.
            frames: 200,
            dt: DT,
            v0: 12.0,
            accel: |_| 0.0,
            lateral: junction_drift,
            collisions: &[],
            // The light stands at the junction's entry, 6.5 m left of the lane.
            others: &[Other::RedLight {
                at: 58.0,
                side: 6.5,
            }],
            status: "Completed",
            score_route: 100.0,
            xml_gap: Some((56.0, 94.0)),
        },
    ]
}

fn simulate(s: &Script) -> Vec<SimFrame> {
    let mut out = Vec::with_capacity(s.frames);
    let (mut x, mut v) = (0.0f64, s.v0);
    let dt = s.dt;
    for i in 0..s.frames {
        let t = i as f64 * dt;
        let a_cmd = (s.accel)(i);
        // The car cannot reverse: braking stops at standstill.
        let a = if v <= 0.0 && a_cmd < 0.0 { 0.0 } else { a_cmd };
        let (y, ay) = (s.lateral)(t);
        out.push(SimFrame {
            loc: [ORIGIN[0] + x, ORIGIN[1] + y],
            acc: [a, ay],
            speed: v,
        });
        v = (v + a * dt).max(0.0);
        x += v * dt;
    }
    out
}

/// Bench2Drive's penalty factor of one infraction list.
fn factor(list: &str) -> f64 {
    match list {
        "collisions_pedestrian" => 0.5,
        "collisions_vehicle" => 0.6,
        "collisions_layout" => 0.65,
        "red_light" => 0.7,
        _ => 1.0,
    }
}

/// Python's `round(x, 6)` for the values used here (no ties occur).
fn round6(x: f64) -> f64 {
    (x * 1e6).round() / 1e6
}

/// A Python-style float repr with 3 decimals at most (as CARLA's collision strings).
fn py3(x: f64) -> String {
    let r = (x * 1000.0).round() / 1000.0;
    let s = format!("{r}");
    if s.contains('.') {
        s
    } else {
        format!("{s}.0")
    }
}

/// Writes the demo run into `dir` and returns the paths it wrote.
///
/// ```
/// let dir = tempfile::tempdir().unwrap();
/// let run = monitor_host::demo::write(dir.path()).unwrap();
/// assert!(run.results.exists() && run.routes.exists());
/// assert_eq!(run.route_ids.len(), 9);
/// ```
pub fn write(dir: &Path) -> Result<DemoRun> {
    write_scripts(dir, &scripts(), Layout::Demo)
}

/// The files of an earlier run in `dir` that [`write()`] or [`write_large`] would overwrite
/// (`results.json`, `routes.xml`, `telemetry`), so that a front end can refuse to destroy a run.
///
/// ```
/// let dir = tempfile::tempdir()?;
/// assert!(monitor_host::demo::existing_run(dir.path()).is_empty());
/// monitor_host::demo::write(dir.path())?;
/// assert_eq!(monitor_host::demo::existing_run(dir.path()).len(), 4);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn existing_run(dir: &Path) -> Vec<PathBuf> {
    ["results.json", "routes.xml", "telemetry", "maps"]
        .iter()
        .map(|n| dir.join(n))
        .filter(|p| std::fs::symlink_metadata(p).is_ok())
        .collect()
}

/// Writes a benchmark-sized run in Bench2Drive's layout (see [`write_large_with`]).
///
/// ```
/// let dir = tempfile::tempdir().unwrap();
/// let run = monitor_host::demo::write_large(dir.path(), 2, 50).unwrap();
/// assert_eq!(run.route_ids.len(), 2);
/// ```
pub fn write_large(dir: &Path, routes: usize, frames: usize) -> Result<DemoRun> {
    write_large_with(dir, routes, frames, LargeLayout::Bench2Drive, 0)
}

/// Writes a benchmark-sized run: `routes` cruising routes of `frames` frames each, of which
/// `collisions` (spread evenly) hit a vehicle at frame 2,000 (routes of more than 2,000 frames:
/// the HTML report's size and load-time benchmark uses 220 routes, 100 collisions).
///
/// Its `metric_info.json` files look like real Bench2Drive ones, so that a throughput in MB/s
/// means what it would on a real run: `json.dump(indent=4)` layout, the keys of `layout`, and
/// CARLA's float32 values written as Python writes the widened float (`0.10000000149011612`),
/// with a little deterministic sensor noise.
///
/// ```
/// use monitor_host::demo::{write_large_with, LargeLayout};
/// let dir = tempfile::tempdir().unwrap();
/// let run = write_large_with(dir.path(), 4, 2100, LargeLayout::Wide, 2).unwrap();
/// assert_eq!(run.route_ids.len(), 4);
/// ```
pub fn write_large_with(
    dir: &Path,
    routes: usize,
    frames: usize,
    layout: LargeLayout,
    collisions: usize,
) -> Result<DemoRun> {
    const HIT: &[(usize, &str, &str)] = &[(2000, "collisions_vehicle", "vehicle.tesla.model3")];
    // Route i collides when the running count of collisions steps up at i.
    let hits = |i: usize| {
        frames > 2000 && (i + 1) * collisions / routes.max(1) > i * collisions / routes.max(1)
    };
    let list: Vec<Script> = (0..routes)
        .map(|i| Script {
            name: "DemoLargeCruising_1",
            xml_id: 910_000 + i as u32,
            frames,
            dt: DT,
            v0: 8.0 + (i % 7) as f64,
            accel: |i| if i % 400 < 40 { 0.5 } else { 0.0 },
            lateral: straight,
            collisions: if hits(i) { HIT } else { &[] },
            others: &[],
            status: "Completed",
            score_route: 100.0,
            xml_gap: None,
        })
        .collect();
    write_scripts(dir, &list, Layout::Realistic(layout))
}

/// How `metric_info.json` is written.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Layout {
    /// The small demo: the required vectors, short decimal values.
    Demo,
    /// Like a real Bench2Drive file (see [`write_large_with`]).
    Realistic(LargeLayout),
}

/// The files of a demo run.
#[derive(Clone, Debug)]
pub struct DemoRun {
    /// The raw evaluator results file.
    pub results: PathBuf,
    /// The telemetry root (`<save_name>/metric_info.json` below it).
    pub telemetry: PathBuf,
    /// The route XML.
    pub routes: PathBuf,
    /// The maps folder (`DemoTown.xodr`, the demo town's map with a junction).
    pub maps: PathBuf,
    /// Route ids, in order.
    pub route_ids: Vec<String>,
}

fn write_scripts(dir: &Path, scripts: &[Script], layout: Layout) -> Result<DemoRun> {
    let telemetry = dir.join("telemetry");
    fs::create_dir_all(&telemetry)
        .map_err(at(format_args!("cannot create {}", telemetry.display())))?;
    let mut records = Vec::new();
    let mut xml = String::from("<?xml version='1.0' encoding='utf-8'?>\n<routes>\n");
    let mut route_ids = Vec::new();
    for (index, s) in scripts.iter().enumerate() {
        let route_id = format!("RouteScenario_{}_rep0", s.xml_id);
        let save_name = format!("{route_id}_{TOWN}_{}_1_11_22_06_00_00", s.name);
        let sim = simulate(s);

        // Telemetry, in Bench2Drive's indented metric_info layout (steps start at 1).
        let folder = telemetry.join(&save_name);
        fs::create_dir_all(&folder)
            .map_err(at(format_args!("cannot create {}", folder.display())))?;
        let path = folder.join("metric_info.json");
        match layout {
            Layout::Demo => write_metric_info(&path, &sim),
            Layout::Realistic(keys) => write_metric_info_realistic(&path, &sim, keys),
        }
        .map_err(at(format_args!("cannot write telemetry of {route_id}")))?;

        // Route XML: a waypoint every 2 m along the road, from 10 m before the start (every
        // 7.5 m in the large run: closer to real route files, still below the 8 m junction gap).
        let spacing = match layout {
            Layout::Demo => 2.0,
            Layout::Realistic(_) => 7.5,
        };
        let length = sim.last().map_or(0.0, |f| f.loc[0] - ORIGIN[0]) + 20.0;
        let _ = writeln!(
            xml,
            "   <route id=\"{}\" town=\"{TOWN}\">\n      <waypoints>",
            s.xml_id
        );
        let mut x = -10.0;
        while x <= length {
            if s.xml_gap.is_some_and(|(a, b)| x > a && x < b) {
                x += spacing;
                continue;
            }
            let _ = writeln!(
                xml,
                "         <position x=\"{:.1}\" y=\"{:.1}\" z=\"0.0\"/>",
                ORIGIN[0] + x,
                ORIGIN[1]
            );
            x += spacing;
        }
        let _ = writeln!(xml, "      </waypoints>\n   </route>");

        // The evaluator's record.
        let mut infractions = serde_json::Map::new();
        for l in crate::input::record::KNOWN_LISTS {
            infractions.insert(l.into(), serde_json::Value::Array(vec![]));
        }
        let mut penalty = 1.0;
        for (n, &(frame, list, type_id)) in s.collisions.iter().enumerate() {
            let f = &sim[frame];
            let msg = format!(
                "Agent collided against object with type={type_id} and id={} at (x={}, y={}, z=0.0)",
                2000 + n,
                py3(f.loc[0]),
                py3(f.loc[1])
            );
            if let Some(serde_json::Value::Array(v)) = infractions.get_mut(list) {
                v.push(msg.into());
            }
            penalty *= factor(list);
        }
        for (n, other) in s.others.iter().enumerate() {
            let (list, msg) = match *other {
                Other::RedLight { at, side } => (
                    "red_light",
                    format!(
                        "Agent ran a red light {} at (x={}, y={}, z=3.0)",
                        3000 + n,
                        py3(ORIGIN[0] + at),
                        py3(ORIGIN[1] + side)
                    ),
                ),
                Other::Blocked => {
                    let f = sim.last().map_or(ORIGIN, |f| f.loc);
                    (
                        "vehicle_blocked",
                        format!(
                            "Agent got blocked at (x={}, y={}, z=0.0)",
                            py3(f[0]),
                            py3(f[1])
                        ),
                    )
                }
            };
            if let Some(serde_json::Value::Array(v)) = infractions.get_mut(list) {
                v.push(msg.into());
            }
            penalty *= factor(list);
        }
        records.push(serde_json::json!({
            "index": index,
            "route_id": route_id,
            "status": s.status,
            "num_infractions": s.collisions.len() + s.others.len(),
            "infractions": infractions,
            "scores": {
                "score_route": s.score_route,
                "score_penalty": penalty,
                "score_composed": round6(s.score_route * penalty),
            },
            "meta": {
                "route_length": length,
                "duration_game": s.frames as f64 * s.dt,
                "duration_system": s.frames as f64 * s.dt * 3.0,
            },
            "save_name": save_name,
            "town_name": TOWN,
            "scenario_name": s.name,
            "weather_id": "1",
        }));
        route_ids.push(route_id);
    }
    xml.push_str("</routes>\n");
    let routes = dir.join("routes.xml");
    fs::write(&routes, xml).map_err(at(format_args!("cannot write {}", routes.display())))?;
    let maps = dir.join("maps");
    fs::create_dir_all(&maps).map_err(at(format_args!("cannot create {}", maps.display())))?;
    let map_file = maps.join(format!("{TOWN}.xodr"));
    fs::write(&map_file, map::xodr(ORIGIN))
        .map_err(at(format_args!("cannot write {}", map_file.display())))?;
    let results = dir.join("results.json");
    let doc = serde_json::json!({
        "_checkpoint": {
            "global_record": {},
            "progress": [scripts.len(), scripts.len()],
            "records": records,
        },
        "entry_status": "Finished",
        "eligible": true,
        "sensors": [],
        "values": [],
        "labels": [],
    });
    let text = serde_json::to_string_pretty(&doc)
        .map_err(|e| at("cannot encode the results")(e.into()))?;
    fs::write(&results, text).map_err(at(format_args!("cannot write {}", results.display())))?;
    Ok(DemoRun {
        results,
        telemetry,
        routes,
        maps,
        route_ids,
    })
}
