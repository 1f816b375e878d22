//! Link proof for `scripts/core-nostd.sh`: a tiny `#![no_std]`, `#![no_main]` binary for a bare
//! Cortex-M target that drives `Monitor::push`, `Monitor::finish`, `json::encode` and
//! `json::decode_frame`. The script links it for `thumbv7em-none-eabihf` and checks with `nm`
//! that no symbol of `std` or `alloc` (`__rust_alloc`, `__rust_dealloc`, `alloc::`, `std::`)
//! made it into the image.
//!
//! On the host (tests, clippy) the same code builds as an ordinary program, so the workspace's
//! `--all-targets` builds need nothing special.
#![cfg_attr(target_os = "none", no_std)]
#![cfg_attr(target_os = "none", no_main)]

use core::hint::black_box;

use monitor_core::{json, Collisions, Config, Event, Frame, Monitor};

/// A static monitor: `nm -S` shows its size on the target (`NOSTD_MONITOR`).
#[cfg_attr(target_os = "none", no_mangle)]
#[used]
static NOSTD_MONITOR: Monitor = Monitor::new_static(Config::DEFAULT);

/// Runs a 45-frame route with opaque inputs and encodes every event and the summary; returns
/// the bytes written (so nothing is optimised away).
fn run() -> usize {
    // Monitor::new validates at run time (the static was validated at compile time).
    let Ok(mut monitor) = Monitor::<20>::new(black_box(Config::DEFAULT)) else {
        return NOSTD_MONITOR.frames() as usize;
    };
    let mut buf = [0u8; 256];
    let mut written = 0usize;
    for i in 0..45u32 {
        let x = black_box(i as f32 * 0.1);
        let frame = Frame {
            collisions: Collisions {
                vehicle: u16::from(i == 30),
                ..Collisions::NONE
            },
            ..Frame::from_vectors(
                [x, 0.5],
                [1.0, 0.0],
                [0.0, -1.0],
                x,
                5.0,
                Some(x),
                Collisions::NONE,
            )
        };
        match monitor.push(black_box(&frame)) {
            Ok(events) => {
                for e in &events {
                    let e: &Event = e;
                    written = written.wrapping_add(json::encode(e, &mut buf).unwrap_or(0));
                }
            }
            Err(_) => return 0,
        }
    }
    // A frame decoded from JSON goes through the same path.
    let text: &[u8] = black_box(br#"{"a_lon":-0.6,"a_lat":0,"a_mag":0.6,"yaw_rate":1,"speed":4}"#);
    if let Ok(frame) = json::decode_frame(text) {
        if monitor.push(&frame).is_err() {
            return 0;
        }
    }
    if let Ok(done) = monitor.finish() {
        written = written.wrapping_add(json::encode(&done.summary, &mut buf).unwrap_or(0));
    }
    black_box(buf);
    written
}

#[cfg(target_os = "none")]
#[no_mangle]
pub extern "C" fn _start() -> ! {
    black_box(run());
    loop {
        core::hint::spin_loop();
    }
}

#[cfg(target_os = "none")]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    loop {
        core::hint::spin_loop();
    }
}

#[cfg(not(target_os = "none"))]
fn main() {
    let n = run();
    assert!(n > 0);
    println!("nostd_link: {n} JSON bytes");
}
