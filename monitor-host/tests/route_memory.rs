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

/// (peak heap while scoring a drive of `seconds`, heap its report holds), bytes.
fn score_drive(seconds: u64) -> (usize, usize) {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join(format!("drive{seconds}.mcap"));
    // A pause every 10 minutes, an event every 5 (the library's writer).
    let weave = monitor_host::demo::drive::Weave {
        seconds,
        ..Default::default()
    };
    monitor_host::demo::drive::write_weave(&log, &weave).unwrap();
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
