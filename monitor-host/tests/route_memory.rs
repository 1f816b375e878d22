//! A run's memory per route and per drive (issue 51): the heap a run needs grows by at most 4 KB a
//! route beyond what its report holds, and not with a vehicle log's length. Measured with a
//! counting allocator (bytes, not time: nothing here races the clock); the tests of this binary
//! take turns ([`SERIAL`]), so that no other test allocates meanwhile.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering::Relaxed};

use monitor_host::Settings;
use monitor_host::{score_run, Inputs};

struct Counting;

static NOW: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

// SAFETY: every call is passed on to the system allocator unchanged; only sizes are counted.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let now = NOW.fetch_add(layout.size(), Relaxed) + layout.size();
        PEAK.fetch_max(now, Relaxed);
        unsafe { System.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        NOW.fetch_sub(layout.size(), Relaxed);
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        if new_size >= layout.size() {
            let now = NOW.fetch_add(new_size - layout.size(), Relaxed) + new_size - layout.size();
            PEAK.fetch_max(now, Relaxed);
        } else {
            NOW.fetch_sub(layout.size() - new_size, Relaxed);
        }
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static ALLOC: Counting = Counting;

/// One test at a time: the counts are the whole process's.
static SERIAL: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// (peak heap while scoring, heap the report holds), in bytes above what was allocated before.
fn score_generated(routes: usize) -> (usize, usize) {
    let dir = tempfile::tempdir().unwrap();
    let run = monitor_host::demo::write_large(dir.path(), routes, 200).unwrap();
    let inputs = Inputs {
        telemetry: Some(run.telemetry.clone()),
        route_xml: Some(run.routes.clone()),
        ..Inputs::new([run.results.clone()])
    };
    let settings = Settings {
        threads: Some(1),
        ..Settings::default()
    };
    let before = NOW.load(Relaxed);
    PEAK.store(before, Relaxed);
    let report = score_run(&inputs, &settings).unwrap();
    let peak = PEAK.load(Relaxed) - before;
    let held = NOW.load(Relaxed).saturating_sub(before);
    assert_eq!(report.routes.len(), routes);
    assert!(!report.has_problems());
    drop(report);
    (peak, held)
}

#[test]
fn i51_1_heap_grows_at_most_4_kb_a_route_beyond_the_report() {
    let _turn = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let (small, n_small) = (score_generated(40), 40);
    let (large, n_large) = (score_generated(240), 240);
    let per_route = |f: fn(&(usize, usize)) -> usize| {
        (f(&large) as f64 - f(&small) as f64) / (n_large - n_small) as f64
    };
    let peak = per_route(|p| p.0);
    let report = per_route(|p| p.1);
    println!("peak heap {peak:.0} B a route, report {report:.0} B a route");
    assert!(report > 0.0, "the report holds its rows");
    assert!(
        peak - report <= 4096.0,
        "peak heap grows {peak:.0} B a route, {:.0} B beyond the report's {report:.0} B",
        peak - report
    );
}

// ---- goal 2: a drive's length ----

/// CDR (little-endian) of the two ROS 2 messages a drive needs, aligned from the 4-byte header.
fn cdr(t: u64, body: &[f64], child: bool) -> Vec<u8> {
    let mut c = vec![0u8, 1, 0, 0];
    let align = |c: &mut Vec<u8>, n: usize| {
        while !(c.len() - 4).is_multiple_of(n) {
            c.push(0);
        }
    };
    let string = |c: &mut Vec<u8>, s: &str| {
        align(c, 4);
        c.extend_from_slice(&(s.len() as u32 + 1).to_le_bytes());
        c.extend_from_slice(s.as_bytes());
        c.push(0);
    };
    c.extend_from_slice(&((t / 1_000_000_000) as u32).to_le_bytes());
    c.extend_from_slice(&((t % 1_000_000_000) as u32).to_le_bytes());
    string(&mut c, "map");
    if child {
        string(&mut c, "base_link");
    }
    for x in body {
        align(&mut c, 8);
        c.extend_from_slice(&x.to_le_bytes());
    }
    c
}

const ODOMETRY: &str = "std_msgs/Header header\nstring child_frame_id\n\
    geometry_msgs/PoseWithCovariance pose\ngeometry_msgs/TwistWithCovariance twist\n";
const IMU: &str = "std_msgs/Header header\ngeometry_msgs/Quaternion orientation\n\
    float64[9] orientation_covariance\ngeometry_msgs/Vector3 angular_velocity\n\
    float64[9] angular_velocity_covariance\ngeometry_msgs/Vector3 linear_acceleration\n\
    float64[9] linear_acceleration_covariance\n";

/// Writes a drive of `seconds` at 20 Hz (odometry and IMU along a weave, an event every 5
/// minutes, a 2 s recorder pause every 10 minutes: a new segment).
fn write_drive(path: &std::path::Path, seconds: u64) {
    use std::collections::BTreeMap;
    let file = std::io::BufWriter::new(std::fs::File::create(path).unwrap());
    let mut w = mcap::WriteOptions::new()
        .chunk_size(Some(1 << 18))
        .compression(None)
        .create(file)
        .unwrap();
    let none = BTreeMap::new();
    let s_odom = w.add_schema("nav_msgs/msg/Odometry", "ros2msg", ODOMETRY.as_bytes());
    let s_imu = w.add_schema("sensor_msgs/msg/Imu", "ros2msg", IMU.as_bytes());
    let s_ev = w.add_schema("std_msgs/msg/Empty", "ros2msg", b"");
    let odom = w
        .add_channel(s_odom.unwrap(), "/odom", "cdr", &none)
        .unwrap();
    let imu = w.add_channel(s_imu.unwrap(), "/imu", "cdr", &none).unwrap();
    let ev = w
        .add_channel(s_ev.unwrap(), "/events", "cdr", &none)
        .unwrap();
    let (mut x, mut y, mut yaw) = (0.0f64, 0.0f64, 0.0f64);
    for i in 0..seconds * 20 {
        if i % 12_000 >= 11_960 {
            continue;
        }
        let t = 1_700_000_000_000_000_000 + i * 50_000_000;
        let s = i as f64 * 0.05;
        let (v, wz) = (8.0 + 2.0 * (s / 40.0).sin(), 0.15 * (s / 7.0).sin());
        yaw += wz * 0.05;
        x += v * yaw.cos() * 0.05;
        y += v * yaw.sin() * 0.05;
        let h = |channel_id| mcap::records::MessageHeader {
            channel_id,
            sequence: i as u32,
            log_time: t,
            publish_time: t,
        };
        let mut pose = vec![x, y, 0.0, 0.0, 0.0, (yaw / 2.0).sin(), (yaw / 2.0).cos()];
        pose.extend([0.0; 36]);
        pose.extend([v, 0.0, 0.0, 0.0, 0.0, wz]);
        pose.extend([0.0; 36]);
        w.write_to_known_channel(&h(odom), &cdr(t, &pose, true))
            .unwrap();
        let mut m = vec![0.0, 0.0, 0.0, 1.0];
        m.extend([0.0; 9]);
        m.extend([0.0, 0.0, wz]);
        m.extend([0.0; 9]);
        m.extend([0.3 * (s / 3.1).sin(), v * wz, 9.8]);
        m.extend([0.0; 9]);
        w.write_to_known_channel(&h(imu), &cdr(t, &m, false))
            .unwrap();
        if i % 6_000 == 3_000 {
            w.write_to_known_channel(&h(ev), &[0, 1, 0, 0]).unwrap();
        }
    }
    w.finish().unwrap();
}

/// (peak heap while scoring a drive of `seconds`, heap its report holds), bytes.
fn score_drive(seconds: u64) -> (usize, usize) {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join(format!("drive{seconds}.mcap"));
    write_drive(&log, seconds);
    // `sds score --mcap LOG --topic event=/events --jobs 1`.
    let request = monitor_host::ScoreRequest {
        logs: vec![log],
        topics: vec!["event=/events".into()],
        settings: monitor_host::RunSettings {
            jobs: Some(1),
            ..Default::default()
        },
        ..Default::default()
    };
    let before = NOW.load(Relaxed);
    PEAK.store(before, Relaxed);
    let report = request.score(&monitor_host::NoProgress).unwrap().report;
    let peak = PEAK.load(Relaxed) - before;
    let held = NOW.load(Relaxed).saturating_sub(before);
    let route = &report.routes[0];
    assert_eq!(route.batch_agrees, Some(true), "{:?}", route.telemetry);
    assert!(
        route.frames > seconds as u32 * 19,
        "{} frames",
        route.frames
    );
    drop(report);
    (peak, held)
}

#[test]
fn i51_2_heap_does_not_grow_with_a_drives_length() {
    let _turn = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let (short, long) = (600, 2400);
    let (a, b) = (score_drive(short), score_drive(long));
    println!(
        "drive of {short} s: peak heap {} B, report {} B; of {long} s: peak {} B, report {} B",
        a.0, a.1, b.0, b.1
    );
    // 36,000 more frames: held as today's frames (0.4 KiB a frame) they would be 14 MB more. What
    // may grow is the report and the chunk verdicts the timeline draws (1,800 more chunks).
    let growth = b.0.saturating_sub(a.0);
    let allowed = b.1.saturating_sub(a.1) + 1_800 * 64;
    assert!(
        growth <= allowed,
        "peak heap grew by {growth} B from a {short} s drive to a {long} s one (allowed {allowed})"
    );
}
