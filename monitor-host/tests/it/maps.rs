//! The map module against closed-form and independently integrated geometry on the hand-made
//! maps of `tests/data/maps` (written by `make_maps.py` there): spiral, poly3, paramPoly3 with
//! both `pRange`s, laneOffset and varying widths, elevation and an overpass; the junction map's
//! gap filling and dense route; the errors of the broken maps; the `--maps` folder layouts; and,
//! on the CARLA towns when `../shared` is present, that the indexed search returns the exact
//! nearest lane.

use std::f64::consts::FRAC_PI_2;
use std::path::{Path, PathBuf};

use monitor_host::geometry::map::{dense_route, Map, MapDir, Projector};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/maps")
        .join(name)
}

fn load(name: &str) -> Map {
    Map::load(&data(name)).unwrap_or_else(|e| panic!("{e}"))
}

/// CARLA point of lane `lane` of road `road` at `s`.
fn at(map: &Map, road: &str, lane: i32, s: f64) -> [f64; 3] {
    let r = map.lane_at(road, lane, s).expect("lane");
    map.lane_point(&r, s).expect("point")
}

/// Composite Simpson: an integration independent of the library's Gauss–Legendre.
fn simpson(f: impl Fn(f64) -> f64, a: f64, b: f64, n: usize) -> f64 {
    let h = (b - a) / n as f64;
    let mut s = f(a) + f(b);
    for i in 1..n {
        s += if i % 2 == 1 { 4.0 } else { 2.0 } * f(a + i as f64 * h);
    }
    s * h / 3.0
}

fn close(a: [f64; 3], b: [f64; 3], tol: f64, what: &str) {
    let d = ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt();
    assert!(d <= tol, "{what}: {a:?} vs {b:?} ({d:e} m apart)");
}

/// A point moved from OpenDRIVE (x, y) along the left normal of heading `h` by `t`, in CARLA's
/// frame.
fn carla(x: f64, y: f64, h: f64, t: f64, z: f64) -> [f64; 3] {
    [x - t * h.sin(), -(y + t * h.cos()), z]
}

#[test]
fn spiral_lanes_follow_the_fresnel_series() {
    let map = load("spiral.xodr");
    // First geometry: curvature 0 -> 0.04 over 50 m, heading a s² with a = 0.0004.
    let a: f64 = 0.04 / 100.0;
    let fresnel = |s: f64| -> (f64, f64) {
        let (mut x, mut y) = (0.0, 0.0);
        let mut fact = 1.0; // n!
        for n in 0..20 {
            if n > 0 {
                fact *= n as f64;
            }
            let term = a.powi(n) * s.powi(2 * n + 1) / (fact * (2 * n + 1) as f64);
            match n % 4 {
                0 => x += term,
                1 => y += term,
                2 => x -= term,
                _ => y -= term,
            }
        }
        (x, y)
    };
    for i in 0..=25 {
        let s = 2.0 * i as f64;
        let (x, y) = fresnel(s);
        let h = a * s * s;
        for (lane, t) in [(1, 1.75), (-1, -1.75), (-2, -5.0)] {
            close(
                at(&map, "1", lane, s),
                carla(x, y, h, t, 0.0),
                1e-9,
                &format!("lane {lane} at s {s}"),
            );
        }
    }
    // Second geometry: curvature 0.04 -> 0 from where the first ends; positions by Simpson.
    let (x1, y1) = fresnel(50.0);
    let h1 = a * 2500.0;
    for i in 1..=10 {
        let u = 5.0 * i as f64;
        let th = |v: f64| h1 + 0.04 * v - 0.0004 * v * v;
        let x = x1 + simpson(|v| th(v).cos(), 0.0, u, 4000);
        let y = y1 + simpson(|v| th(v).sin(), 0.0, u, 4000);
        close(
            at(&map, "1", -1, 50.0 + u),
            carla(x, y, th(u), -1.75, 0.0),
            1e-9,
            &format!("s {}", 50.0 + u),
        );
    }
}

#[test]
fn poly3_is_evaluated_by_arc_length_with_elevation() {
    let map = load("poly3.xodr");
    let (a, c, d) = (0.5, 0.01, -0.0001);
    let dv = |u: f64| 2.0 * c * u + 3.0 * d * u * u;
    let (h0, x0, y0) = (0.3f64, 10.0, 5.0);
    for i in 0..=8 {
        let u = 5.0 * i as f64;
        let s = simpson(|w| (1.0 + dv(w) * dv(w)).sqrt(), 0.0, u, 4000);
        let v = a + c * u * u + d * u * u * u;
        let (x, y) = (
            x0 + u * h0.cos() - v * h0.sin(),
            y0 + u * h0.sin() + v * h0.cos(),
        );
        let h = h0 + dv(u).atan();
        let z = 1.0 + 0.05 * s + 0.001 * s * s - 0.00001 * s * s * s;
        for (lane, t) in [(1, 1.75), (-1, -1.75)] {
            close(
                at(&map, "1", lane, s),
                carla(x, y, h, t, z),
                1e-9,
                &format!("lane {lane} at u {u}"),
            );
        }
    }
}

#[test]
fn param_poly3_both_ranges_by_arc_length() {
    let map = load("parampoly3.xodr");
    // (road, u, v, p_end, start x, y, hdg)
    let xml = std::fs::read_to_string(data("parampoly3.xodr")).unwrap();
    let bu: f64 = xml
        .split("bU=\"")
        .nth(1)
        .unwrap()
        .split('"')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    let cases = [
        (
            "1",
            [0.0, bu, -0.004, 0.0],
            [0.0, 0.0, 0.02, -0.0003],
            30.0,
            0.0,
            0.0,
            0.1f64,
        ),
        (
            "2",
            [0.0, 35.0, -6.0, 1.0],
            [0.0, 2.0, 9.0, -4.0],
            1.0,
            0.0,
            100.0,
            -0.2,
        ),
    ];
    for (road, u, v, p_end, x0, y0, h0) in cases {
        let poly = |c: [f64; 4], p: f64| c[0] + p * (c[1] + p * (c[2] + p * c[3]));
        let der = |c: [f64; 4], p: f64| c[1] + p * (2.0 * c[2] + p * 3.0 * c[3]);
        for i in 0..=10 {
            let p = p_end * i as f64 / 10.0;
            let s = simpson(|q| der(u, q).hypot(der(v, q)), 0.0, p, 4000);
            let (lu, lv) = (poly(u, p), poly(v, p));
            let (x, y) = (
                x0 + lu * h0.cos() - lv * h0.sin(),
                y0 + lu * h0.sin() + lv * h0.cos(),
            );
            let h = h0 + der(v, p).atan2(der(u, p));
            close(
                at(&map, road, -1, s),
                carla(x, y, h, -1.75, 0.0),
                1e-9,
                &format!("road {road} p {p}"),
            );
        }
    }
}

#[test]
fn lane_offset_and_widths_on_a_straight_road() {
    let map = load("lane_offset.xodr");
    let offset = |s: f64| {
        if s < 40.0 {
            0.5 + 0.02 * s - 0.001 * s * s + 0.00001 * s * s * s
        } else {
            -0.3
        }
    };
    let w_right = |s: f64| {
        if s < 30.0 {
            3.0 + 0.001 * s * s - 0.00001 * s * s * s
        } else if s < 40.0 {
            3.6
        } else {
            3.6 - 0.01 * (s - 40.0)
        }
    };
    let w_left = |s: f64| if s < 40.0 { 3.0 + 0.01 * s } else { 3.4 };
    // Slope of lane -1's centre (OpenDRIVE y = offset - width / 2) inside section 0.
    let slope = |s: f64| {
        let d_off = 0.02 - 0.002 * s + 0.00003 * s * s;
        let d_w = if s < 30.0 {
            0.002 * s - 0.00003 * s * s
        } else {
            0.0
        };
        d_off - d_w / 2.0
    };
    for i in 0..=79 {
        let s = i as f64 + 0.25;
        let y1 = offset(s) + w_left(s) / 2.0;
        let ym1 = offset(s) - w_right(s) / 2.0;
        close(
            at(&map, "1", 1, s),
            [s, -y1, 0.0],
            1e-12,
            &format!("lane 1 at {s}"),
        );
        close(
            at(&map, "1", -1, s),
            [s, -ym1, 0.0],
            1e-12,
            &format!("lane -1 at {s}"),
        );
        if s >= 40.0 {
            let w2 = 0.1 * (s - 40.0);
            let ym2 = offset(s) - w_right(s) - w2 / 2.0;
            close(
                at(&map, "1", -2, s),
                [s, -ym2, 0.0],
                1e-12,
                &format!("lane -2 at {s}"),
            );
        }
        // A point 0.4 m right of lane -1's centre (CARLA y grows to the right): its foot lies on
        // the closed-form centre line and the offset is perpendicular to the lane there.
        if s < 29.0 {
            let p = map.project(s, -ym1 + 0.4, 0.0).expect("projection");
            assert_eq!(
                (map.road_id(p.lane.road), p.lane.lane),
                ("1", -1),
                "at s {s}"
            );
            let f = p.foot;
            assert!((p.s - f[0]).abs() < 1e-12);
            assert!(
                (-f[1] - (offset(f[0]) - w_right(f[0]) / 2.0)).abs() < 1e-12,
                "foot at {s}"
            );
            let (dx, dy) = (s - f[0], -(-ym1 + 0.4) - -f[1]);
            assert!(
                (dx + dy * slope(f[0])).abs() < 1e-9,
                "not perpendicular at s {s}"
            );
            assert!((p.distance_2d - dx.hypot(dy)).abs() < 1e-12);
            assert!(p.distance_2d < 0.4 && p.distance_2d > 0.39);
            assert!((p.width - w_right(f[0])).abs() < 1e-12, "width at s {s}");
        }
        // Past s = 40 lane 1 runs parallel to x: the foot is straight across.
        if s > 41.0 {
            let p = map.project(s, -y1 - 0.4, 0.0).expect("projection");
            assert_eq!(p.lane.lane, 1);
            assert!((p.distance_2d - 0.4).abs() < 1e-9 && (p.s - s).abs() < 1e-9);
            assert!((p.width - 3.4).abs() < 1e-12);
        }
    }
    // Lane -1 jumps where its width record changes (s = 30: 3.63 -> 3.6) and where the
    // section and laneOffset change (s = 40): the lane ends at its limit from inside.
    let end = map
        .lane_point(&map.lane_at("1", -1, 39.0).unwrap(), 40.0)
        .unwrap();
    close(
        end,
        [40.0, -(offset(39.999_999_999) - 3.6 / 2.0), 0.0],
        1e-6,
        "section end",
    );
    // The shoulder of section 0 is not a driving lane; lane -2 of section 1 is.
    let p = map
        .project(10.0, -(offset(10.0) - w_right(10.0) - 0.5), 0.0)
        .unwrap();
    assert_eq!(p.lane.lane, -1);
}

#[test]
fn overpass_points_project_onto_their_own_level() {
    let map = load("overpass.xodr");
    // Under the crossing, 0.3 m from road 1's lane -1 and from road 2's lane -1 in 2-D alike.
    let below = map.project(1.75, 1.75, 0.2).unwrap();
    assert_eq!(map.road_id(below.lane.road), "1");
    assert!((below.foot_z - 0.0).abs() < 1e-12);
    let above = map.project(1.75, 1.75, 8.1).unwrap();
    assert_eq!(map.road_id(above.lane.road), "2");
    assert!((above.foot_z - 8.0).abs() < 1e-12);
    // 2-D distances are reported even though the lane was chosen in 3-D.
    assert!(below.distance_3d > below.distance_2d - 1e-12);
}

#[test]
fn junction_gaps_are_filled_with_the_shortest_lane_chain() {
    let map = load("junction.xodr");
    // P on road 1's eastbound lane -1 (CARLA y = +1.75), 10 m before the junction.
    let p = [-10.0, 1.75, 0.0];
    // Straight on: road 1 (10 m) + road 10 (20 m) + road 2 (10 m).
    let q = [30.0, 1.75, 0.0];
    let pts = map.fill_gap(p, q).expect("straight chain");
    assert_eq!(pts.first(), Some(&[-10.0, 1.75]));
    assert_eq!(pts.last(), Some(&[30.0, 1.75]));
    assert!(pts.iter().all(|pt| (pt[1] - 1.75).abs() < 1e-9));
    let len: f64 = pts
        .windows(2)
        .map(|w| (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]))
        .sum();
    assert!((len - 40.0).abs() < 1e-9);
    assert!(pts
        .windows(2)
        .all(|w| (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]) <= 0.5 + 1e-9));

    // Right turn (CARLA: y grows to the south... OpenDRIVE south is CARLA +y): road 11 turns
    // right with radius 10 about OpenDRIVE (0, -10); its lane -1 is on the inside (8.25 m).
    let q = [8.25, 20.0, 0.0];
    let pts = map.fill_gap(p, q).expect("right-turn chain");
    assert_eq!(pts.last(), Some(&[8.25, 20.0]));
    let on_arc: Vec<&[f64; 2]> = pts
        .iter()
        .filter(|pt| pt[0] > 1e-9 && pt[1] < 10.0 - 1e-9)
        .collect();
    assert!(!on_arc.is_empty());
    for pt in on_arc {
        let r = pt[0].hypot(pt[1] - 10.0);
        assert!(
            (r - 8.25).abs() < 1e-9,
            "{pt:?} is {r} m from the turn's centre"
        );
    }
    // Chords of at most 0.5 m of centre-line length: on the arc, chord <= arc length.
    let arc_len = 10.0 + FRAC_PI_2 * 8.25 + 10.0;
    let n = pts.len() - 1;
    assert!(
        n as f64 >= arc_len / 0.5 - 1e-9,
        "{n} pieces for {arc_len} m"
    );
    // At the junction's entry road 1 ends where roads 10, 11 and 12 start: four tied lanes.
    // The projection takes the smallest road id; the chain takes whichever tied lane leads to
    // Q by the shortest chain (here road 11, the right turn).
    let entry = [0.0, 1.75, 0.0];
    let tied = map.project_tied(entry[0], entry[1], entry[2]);
    let ids: Vec<&str> = tied.iter().map(|t| map.road_id(t.lane.road)).collect();
    assert_eq!(ids, ["1", "10", "11", "12"]);
    assert!(tied.iter().all(|t| t.tied == 4 && t.distance_2d < 1e-12));
    assert_eq!(
        map.road_id(map.project(entry[0], entry[1], entry[2]).unwrap().lane.road),
        "1"
    );
    let turn = map.fill_gap(entry, q).expect("chain from the tied entry");
    let turn_len: f64 = turn
        .windows(2)
        .map(|w| (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]))
        .sum();
    assert!(
        (turn_len - (FRAC_PI_2 * 8.25 + 10.0)).abs() < 0.01,
        "{turn_len}"
    );
    // Against the driving direction there is no chain; nor from a lane without successors.
    assert!(map.fill_gap(q, p).is_none());
    assert!(map
        .fill_gap([30.0, -1.75, 0.0], [-10.0, -1.75, 0.0])
        .is_none());
}

#[test]
fn dense_route_samples_every_metre_and_marks_the_junction() {
    let map = load("junction.xodr");
    let wps = [
        [-30.0, 1.75, 0.0],
        [-28.0, 1.75, 0.0],
        [-10.0, 1.75, 0.0],
        [8.25, 20.0, 0.0],
    ];
    let dense = dense_route(&wps, 8.0, Some(&map));
    // Pair 1 (2 m): 0 m only (1 m is closer than 2 m to Q... 1 m from Q: stop there).
    assert_eq!(dense[0].xy, [-30.0, 1.75]);
    assert_eq!(dense[1].xy, [-29.0, 1.75]);
    assert_eq!(dense[2].xy, [-28.0, 1.75]);
    // Every sample of the filled gap lies on a lane centre; those on road 11 are in the junction.
    let in_junction: Vec<bool> = dense.iter().map(|s| s.in_junction.unwrap()).collect();
    assert!(in_junction.iter().any(|&j| j));
    for s in &dense {
        let pr = map.project(s.xy[0], s.xy[1], 0.0).unwrap();
        let on_turn = s.xy[0] > 1e-9 && s.xy[1] < 10.0 - 1e-9;
        // Samples are on chords of <= 0.5 m: within a few mm of the centre line.
        assert!(
            pr.distance_2d < 5e-3,
            "{:?} is {} m off",
            s.xy,
            pr.distance_2d
        );
        if on_turn && s.xy[0] > 0.5 && s.xy[1] < 9.5 {
            assert_eq!(s.in_junction, Some(true), "{:?}", s.xy);
        }
        if s.xy[0] < -1.0 || s.xy[1] > 11.0 {
            assert_eq!(s.in_junction, Some(false), "{:?}", s.xy);
        }
    }
    // The last sample is the first one closer than 2 m to the last waypoint.
    let last = dense.last().unwrap().xy;
    assert!((last[0] - 8.25).hypot(last[1] - 20.0) < 2.0);
    // Without a map the gap is the straight segment and nothing is known about junctions.
    let plain = dense_route(&wps, 8.0, None);
    assert!(plain.iter().all(|s| s.in_junction.is_none()));
    let gap = ((8.25f64 + 10.0).hypot(20.0 - 1.75) - 2.0).floor() as usize + 1;
    assert!(plain.len() >= 3 + 18 + gap - 1);
}

#[test]
fn broken_maps_name_the_file_and_the_element() {
    let cases = [
        ("broken_truncated.xodr", "not a well-formed OpenDRIVE file"),
        (
            "broken_negative_length.xodr",
            "road 7, geometry 1: negative length -30",
        ),
        (
            "broken_plan_gap.xodr",
            "road 8, geometry 1: starts at s = 30 but the reference line so far ends at s = 20",
        ),
        (
            // Past its one 50 m spiral the road would coil for 99,950 m.
            "broken_road_length.xodr",
            "road 9: length 100000 m, but its geometries end at s = 50",
        ),
        (
            "broken_border.xodr",
            "road 5, lane section 0, lane -2: the lane is given by <border> records",
        ),
        (
            "broken_missing_road.xodr",
            "road 3, successor: links to road \"42\", which is not in the map",
        ),
    ];
    for (file, expected) in cases {
        let err = Map::load(&data(file)).expect_err(file).to_string();
        assert!(err.contains(file), "{err}");
        assert!(err.contains(expected), "{file}: {err}");
    }
    let err = Map::load(&data("no_such_town.xodr"))
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("no_such_town.xodr: cannot read the map"),
        "{err}"
    );
}

#[test]
fn map_lookup_tries_the_four_layouts_in_order() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path();
    let found = |town: &str| MapDir::new(root).find(town);
    assert_eq!(found("Town01"), None);
    let layouts = [
        root.join("Town01/OpenDrive/Town01.xodr"),
        root.join("OpenDrive/Town01.xodr"),
        root.join("Town01_Opt.xodr"),
        root.join("Town01.xodr"),
    ];
    // Add them from the last-tried to the first-tried: each addition takes over.
    for path in &layouts {
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(path, "<OpenDRIVE/>").unwrap();
        assert_eq!(found("Town01").as_ref(), Some(path));
    }
    assert_eq!(found("Town02"), None);
    assert_eq!(found("../Town01"), None);
    // A folder named like a map is found, and refused when read, naming it (issue 29: never a
    // silent "no map").
    let folder = root.join("Town03.xodr");
    std::fs::create_dir_all(&folder).unwrap();
    assert_eq!(found("Town03").as_ref(), Some(&folder));
    let err = Map::load(&folder).unwrap_err().to_string();
    assert!(err.contains("Town03.xodr"), "{err}");
}

fn town(name: &str) -> Option<Map> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join(format!("../../shared/fixtures/maps/{name}.xodr"));
    if !path.is_file() {
        eprintln!(
            "SKIP: {} not found (the CARLA towns live in ../shared)",
            path.display()
        );
        return None;
    }
    Some(Map::load(&path).unwrap_or_else(|e| panic!("{e}")))
}

/// splitmix64, for seeded points.
fn rng(state: &mut u64) -> f64 {
    *state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
}

#[test]
fn indexed_search_finds_the_exact_nearest_lane_on_real_towns() {
    for name in ["Town01", "Town04"] {
        let Some(map) = town(name) else { return };
        let lanes = map.lanes();
        let mut state = 7;
        for _ in 0..300 {
            let l = lanes[(rng(&mut state) * lanes.len() as f64) as usize];
            let s = l.s0 + rng(&mut state) * (l.s1 - l.s0);
            let c = map.lane_point(&l.lane, s).unwrap();
            let p = [
                c[0] + 8.0 * (rng(&mut state) - 0.5),
                c[1] + 8.0 * (rng(&mut state) - 0.5),
                c[2] + 0.3,
            ];
            let best = map.project(p[0], p[1], p[2]).unwrap();
            // With a margin of 10 km every piece of every lane is solved: no pruning at all.
            let all = map.project_within(p[0], p[1], p[2], 1e4);
            assert_eq!(all.len(), lanes.len(), "every lane is reported");
            let min = all
                .iter()
                .map(|a| a.distance_3d)
                .fold(f64::INFINITY, f64::min);
            assert!(
                (best.distance_3d - min).abs() <= 1e-3,
                "{name} {p:?}: {} vs {min}",
                best.distance_3d
            );
            assert!(best.distance_3d <= min + 1e-3);
        }
    }
}

/// Drives `points` through two `Projector`s (`project` and `width`) and checks every answer
/// against `Map::project` bit for bit; returns how many answers took the clearance shortcut.
fn drive_equals_plain(map: &Map, points: &[[f64; 3]]) -> u64 {
    let (mut full, mut width) = (Projector::new(map), Projector::new(map));
    for p in points {
        let plain = map.project(p[0], p[1], p[2]);
        // Debug text is exact for f64 (shortest round trip, and -0 is not 0).
        assert_eq!(
            format!("{:?}", full.project(p[0], p[1], p[2])),
            format!("{plain:?}"),
            "{p:?}"
        );
        assert_eq!(
            width.width(p[0], p[1], p[2]).map(f64::to_bits),
            plain.map(|q| q.width.to_bits()),
            "{p:?}"
        );
    }
    full.shortcuts() + width.shortcuts()
}

#[test]
fn projector_shortcut_equals_the_search_where_lanes_and_records_change() {
    // lane_offset.xodr: along s, the right lane's width record changes at s = 30 (cubic to
    // constant), the lane offset's at s = 40, and a new lane section at s = 40 turns lane -2
    // from a shoulder into a driving lane growing from zero width (so the lane under a point
    // changes). Drives along each lane with a sideways wobble, and drives that change lanes
    // diagonally, at 0.25 m per frame; the other hand-made maps add curves, elevation, an
    // overpass and a junction.
    let mut state = 7;
    let mut total = 0;
    for name in [
        "lane_offset.xodr",
        "junction.xodr",
        "overpass.xodr",
        "spiral.xodr",
        "poly3.xodr",
        "parampoly3.xodr",
    ] {
        let map = load(name);
        let mut shortcuts = 0;
        let mut frames = 0;
        for l in map.lanes() {
            let mut pts = Vec::new();
            let mut s = l.s0;
            while s <= l.s1 {
                let c = map.lane_point(&l.lane, s).unwrap();
                let w = 1.2 * (rng(&mut state) - 0.5);
                pts.push([c[0] + w, c[1] - w, c[2]]);
                s += 0.25;
            }
            if !l.forward {
                pts.reverse();
            }
            frames += pts.len();
            shortcuts += drive_equals_plain(&map, &pts);
        }
        // Lane changes: from each lane's start to another lane's end, straight across.
        let lanes = map.lanes();
        for (a, b) in lanes.iter().zip(lanes.iter().cycle().skip(1)) {
            let p = map.lane_point(&a.lane, a.s0).unwrap();
            let q = map.lane_point(&b.lane, b.s1).unwrap();
            let n = ((q[0] - p[0]).hypot(q[1] - p[1]) / 0.25).ceil().max(1.0) as usize;
            let pts: Vec<[f64; 3]> = (0..=n)
                .map(|i| {
                    let f = i as f64 / n as f64;
                    [0, 1, 2].map(|k| p[k] + f * (q[k] - p[k]))
                })
                .collect();
            frames += pts.len();
            shortcuts += drive_equals_plain(&map, &pts);
        }
        eprintln!("{name}: {shortcuts} shortcuts in {} answers", 2 * frames);
        assert!(shortcuts > 0, "{name}: the shortcut never applied");
        total += shortcuts;
    }
    assert!(total > 1000, "{total}");
}

#[test]
fn projector_with_history_equals_plain_projection() {
    let Some(map) = town("Town04") else { return };
    let lanes = map.lanes();
    let mut state = 11;
    let mut projector = Projector::new(&map);
    let mut widths = Projector::new(&map);
    let mut frames = 0;
    for _ in 0..20 {
        let l = lanes[(rng(&mut state) * lanes.len() as f64) as usize];
        // A "drive" along the lane, wobbling sideways, 0.5 m per frame.
        let mut s = l.s0;
        while s <= l.s1 {
            let c = map.lane_point(&l.lane, s).unwrap();
            let p = [
                c[0] + 3.0 * (rng(&mut state) - 0.5),
                c[1] + 3.0 * (rng(&mut state) - 0.5),
                c[2],
            ];
            let plain = map.project(p[0], p[1], p[2]);
            assert_eq!(
                format!("{:?}", projector.project(p[0], p[1], p[2])),
                format!("{plain:?}")
            );
            assert_eq!(
                widths.width(p[0], p[1], p[2]).map(f64::to_bits),
                plain.map(|q| q.width.to_bits())
            );
            frames += 1;
            s += 0.5;
        }
    }
    // Most frames are answered inside a piece's clearance (a wobble of up to 1.5 m crosses
    // into the next lane's reach now and then).
    eprintln!(
        "Town04: {} + {} shortcuts in 2 x {frames} frames",
        projector.shortcuts(),
        widths.shortcuts()
    );
    assert!(
        projector.shortcuts() > frames / 4,
        "{}",
        projector.shortcuts()
    );
}

/// `--maps` on the real CARLA towns and real routes.
mod real;
