//! Shared by the core benches: a deterministic table of realistic monitor frames.
//!
//! Cruising at 8-12 m/s with small sensor noise, a gentle acceleration phase every 400 frames
//! and a lateral error that is known (the reference is followed within a few decimetres), as
//! the `sds demo --large` run produces. The table is built once; its cost does not depend on
//! the number of frames pushed.

use monitor_core::{Collisions, Frame};

/// Frames in the table (a multiple of the chunk length, 20).
pub const TABLE: usize = 400;

/// A deterministic pseudo-random number in [-1, 1) (splitmix64).
fn noise(i: usize, channel: u64) -> f32 {
    let mut z = (i as u64)
        .wrapping_mul(0x9E37_79B9_7F4A_7C15)
        .wrapping_add(channel.wrapping_mul(0xBF58_476D_1CE4_E5B9));
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    ((z >> 40) as f32 / (1u64 << 23) as f32) - 1.0
}

/// The frame table.
pub fn table() -> Vec<Frame> {
    (0..TABLE)
        .map(|i| {
            let a = if i % 400 < 40 { 0.5 } else { 0.0 } + 0.02 * noise(i, 1);
            let heading = 0.01 * noise(i, 2);
            Frame::from_vectors(
                [a, 0.02 * noise(i, 3)],
                [1.0, heading],
                [-heading, 1.0],
                0.5 * noise(i, 4),
                10.0 + noise(i, 5),
                Some(0.2 + 0.1 * noise(i, 6)),
                Collisions::NONE,
            )
        })
        .collect()
}
