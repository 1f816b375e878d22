//! The compact frame table compiled into flash: written by `build.rs` (which includes this file
//! with `#[path]`), read on the target by [`FlashFrames`](crate::FlashFrames).
//!
//! Layout, all little-endian:
//!
//! ```text
//! header (12 bytes): b"SDSF", version u8 = 2, record length u8 = 33, routes u16, frames u32
//! per route:         frames u32, then that many records
//! record (33 bytes): a_lon, a_lat, a_mag, yaw_rate, speed, lat_err   f32 bits (6 x 4 bytes)
//!                    pedestrian, vehicle, layout, workzone           u16 (4 x 2 bytes)
//!                    flags u8: bit 0 = lat_err known (its bits are 0 when unknown)
//! ```
//!
//! Floats are stored as their IEEE bits, so decoding is exact: the firmware sees the very `f32`s
//! the host decoded from the JSONL.

use monitor_core::{Collisions, Frame};

/// Magic bytes at the start of the table.
pub const MAGIC: [u8; 4] = *b"SDSF";
/// Format version.
pub const VERSION: u8 = 2;
/// Header length in bytes.
pub const HEADER_LEN: usize = 12;
/// Record length in bytes (one frame).
pub const RECORD_LEN: usize = 33;
/// Flag bit: `lat_err` is known.
pub const LAT_ERR_KNOWN: u8 = 1;

/// The table header for `routes` routes of `count` frames in all.
pub const fn header(routes: u16, count: u32) -> [u8; HEADER_LEN] {
    let c = count.to_le_bytes();
    let r = routes.to_le_bytes();
    [
        MAGIC[0],
        MAGIC[1],
        MAGIC[2],
        MAGIC[3],
        VERSION,
        RECORD_LEN as u8,
        r[0],
        r[1],
        c[0],
        c[1],
        c[2],
        c[3],
    ]
}

/// Parses a header: (routes, frames in all), or `None` when the bytes are not a version-2 table.
pub fn parse_header(h: &[u8; HEADER_LEN]) -> Option<(u16, u32)> {
    let [m0, m1, m2, m3, version, len, r0, r1, c0, c1, c2, c3] = *h;
    if [m0, m1, m2, m3] != MAGIC || version != VERSION || usize::from(len) != RECORD_LEN {
        return None;
    }
    Some((
        u16::from_le_bytes([r0, r1]),
        u32::from_le_bytes([c0, c1, c2, c3]),
    ))
}

/// One frame as a record.
pub fn encode_record(f: &Frame) -> [u8; RECORD_LEN] {
    let mut r = [0u8; RECORD_LEN];
    let floats = [
        f.a_lon,
        f.a_lat,
        f.a_mag,
        f.yaw_rate,
        f.speed,
        f.lat_err.unwrap_or(0.0),
    ];
    let counts = [
        f.collisions.pedestrian,
        f.collisions.vehicle,
        f.collisions.layout,
        f.collisions.workzone,
    ];
    let mut bytes = floats
        .iter()
        .flat_map(|x| x.to_bits().to_le_bytes())
        .chain(counts.iter().flat_map(|c| c.to_le_bytes()))
        .chain([if f.lat_err.is_some() {
            LAT_ERR_KNOWN
        } else {
            0
        }]);
    for slot in r.iter_mut() {
        *slot = bytes.next().unwrap_or(0);
    }
    r
}

/// One record as a frame (exact: floats are rebuilt from their bits).
pub fn decode_record(r: &[u8; RECORD_LEN]) -> Frame {
    let f = |i: usize| f32::from_bits(u32::from_le_bytes([r[i], r[i + 1], r[i + 2], r[i + 3]]));
    let c = |i: usize| u16::from_le_bytes([r[i], r[i + 1]]);
    Frame {
        a_lon: f(0),
        a_lat: f(4),
        a_mag: f(8),
        yaw_rate: f(12),
        speed: f(16),
        lat_err: if r[32] & LAT_ERR_KNOWN != 0 {
            Some(f(20))
        } else {
            None
        },
        collisions: Collisions {
            pedestrian: c(24),
            vehicle: c(26),
            layout: c(28),
            workzone: c(30),
        },
    }
}
