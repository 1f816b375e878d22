//! `monitor_host::geometry::map::Map::parse` on arbitrary text: never panics; an error names the
//! file; a map that loads answers projections, gap fills and a dense route without panicking,
//! with finite distances.
#![no_main]

use libfuzzer_sys::fuzz_target;
use monitor_host::geometry::map::{dense_route, Map};

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    match Map::parse(&text, "fuzz.xodr") {
        Ok(map) => {
            let pts = [[0.0, 0.0, 0.0], [5.0, -1.75, 0.0], [30.0, 2.0, 1.0], [-1e9, 3e9, 0.0]];
            for p in pts {
                if let Some(pr) = map.project(p[0], p[1], p[2]) {
                    assert!(pr.distance_3d >= 0.0 && pr.tied >= 1);
                }
            }
            let _ = map.fill_gap(pts[0], pts[2]);
            let _ = dense_route(&pts[..3], 8.0, Some(&map));
        }
        Err(e) => {
            let msg = e.to_string();
            assert!(msg.starts_with("fuzz.xodr: "), "error does not name the file: {msg}");
        }
    }
});
