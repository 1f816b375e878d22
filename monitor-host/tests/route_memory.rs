//! A run's memory per route (issue 51): the heap a run needs grows by at most 4 KB a route beyond
//! what its report holds. Measured with a counting allocator (bytes, not time: nothing here races
//! the clock); one test in this binary, so that no other test allocates meanwhile.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering::Relaxed};

use monitor_host::app::run::{score_run, Inputs};
use monitor_host::Settings;

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
