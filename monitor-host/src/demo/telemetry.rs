//! The demo's telemetry files: `metric_info.json` in Bench2Drive's indented layout (the small
//! demo) or in the realistic layout of real runs with sensor noise (the large run).

use std::fmt::Write as _;
use std::fs;
use std::io::{BufWriter, Write};
use std::path::Path;

use super::frame::{LargeLayout, SimFrame};

pub(super) fn write_metric_info(path: &Path, sim: &[SimFrame]) -> std::io::Result<()> {
    let mut w = BufWriter::new(fs::File::create(path)?);
    w.write_all(b"{")?;
    for (i, f) in sim.iter().enumerate() {
        let sep = if i == 0 { "" } else { "," };
        // Heading is +x: forward (1, 0), right (0, 1) in CARLA's left-handed frame.
        write!(
            w,
            "{sep}\n    \"{step}\": {{\n        \"acceleration\": [\n            {ax},\n            {ay},\n            0.0\n        ],\n        \"angular_velocity\": [\n            0.0,\n            0.0,\n            0.0\n        ],\n        \"forward_vector\": [\n            1.0,\n            0.0,\n            0.0\n        ],\n        \"right_vector\": [\n            0.0,\n            1.0,\n            0.0\n        ],\n        \"location\": [\n            {x},\n            {y},\n            0.0\n        ],\n        \"rotation\": [\n            0.0,\n            0.0,\n            0.0\n        ],\n        \"velocity\": [\n            {v},\n            0.0,\n            0.0\n        ]\n    }}",
            step = i + 1,
            ax = fmt_f(f.acc[0]),
            ay = fmt_f(f.acc[1]),
            x = fmt_f(f.loc[0]),
            y = fmt_f(f.loc[1]),
            v = fmt_f(f.speed),
        )?;
    }
    w.write_all(b"\n}\n")?;
    w.flush()?;
    Ok(())
}

/// A deterministic pseudo-random number in [-1, 1) for (frame, channel): sensor noise.
fn noise(frame: usize, channel: u64) -> f64 {
    // splitmix64 of the pair.
    let mut z = (frame as u64)
        .wrapping_mul(0x9E37_79B9_7F4A_7C15)
        .wrapping_add(channel.wrapping_mul(0xBF58_476D_1CE4_E5B9));
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}

/// A CARLA float32 as Python writes it after widening to float (`0.10000000149011612`).
fn py_f32(x: f64) -> String {
    // Python writes 1e-05 where Rust writes 1e-5: both are valid JSON numbers.
    format!("{:?}", f64::from(x as f32))
}

/// A Python float (shortest round-trip repr, always with a decimal point or exponent).
fn py_f64(x: f64) -> String {
    format!("{x:?}")
}

/// One frame of a realistic `metric_info.json` (see [`write_large_with`]):
/// `json.dump(indent=4)` of the keys of `layout`.
///
/// [`write_large_with`]: super::write_large_with
fn realistic_frame(out: &mut String, step: usize, f: &SimFrame, layout: LargeLayout) {
    let wide = layout == LargeLayout::Wide;
    let n = |c: u64| noise(step, c);
    // Small heading wobble (deg) and yaw rate noise around straight +x driving.
    let yaw = 0.05 * n(1);
    let (s, c) = yaw.to_radians().sin_cos();
    let vec3 = |out: &mut String, key: &str, v: [String; 3], last: bool| {
        let _ = write!(
            out,
            "        \"{key}\": [\n            {},\n            {},\n            {}\n        ]{}\n",
            v[0],
            v[1],
            v[2],
            if last { "" } else { "," }
        );
    };
    let scalar = |out: &mut String, key: &str, v: String, last: bool| {
        let _ = writeln!(out, "        \"{key}\": {v}{}", if last { "" } else { "," });
    };
    let _ = writeln!(out, "    \"{}\": {{", step + 1);
    vec3(
        out,
        "acceleration",
        [
            py_f32(f.acc[0] + 0.002 * n(2)),
            py_f32(f.acc[1] + 0.002 * n(3)),
            py_f32(0.001 * n(4)),
        ],
        false,
    );
    vec3(
        out,
        "angular_velocity",
        [
            py_f32(0.01 * n(5)),
            py_f32(0.01 * n(6)),
            py_f32(0.02 * n(7)),
        ],
        false,
    );
    vec3(
        out,
        "forward_vector",
        [py_f32(c), py_f32(s), py_f32(1e-4 * n(8))],
        false,
    );
    vec3(
        out,
        "right_vector",
        [py_f32(-s), py_f32(c), py_f32(1e-4 * n(9))],
        false,
    );
    vec3(
        out,
        "location",
        [
            py_f32(f.loc[0]),
            py_f32(f.loc[1]),
            py_f32(0.0017 + 1e-4 * n(10)),
        ],
        false,
    );
    vec3(
        out,
        "rotation",
        [py_f32(0.01 * n(11)), py_f32(yaw), py_f32(0.01 * n(12))],
        !wide,
    );
    if !wide {
        out.push_str("    }");
        return;
    }
    vec3(
        out,
        "velocity",
        [
            py_f32(f.speed * c),
            py_f32(f.speed * s),
            py_f32(1e-3 * n(13)),
        ],
        false,
    );
    scalar(out, "speed", py_f64(f.speed + 1e-3 * n(14)), false);
    scalar(out, "throttle", py_f32(0.5 + 0.25 * n(15)), false);
    scalar(out, "steer", py_f32(0.01 * n(16)), false);
    scalar(out, "brake", "0.0".into(), false);
    vec3(
        out,
        "gps",
        [
            py_f64(-0.002 - f.loc[1] * 9e-6 + 1e-9 * n(17)),
            py_f64(0.001 + f.loc[0] * 9e-6 + 1e-9 * n(18)),
            py_f32(0.0017 + 1e-4 * n(19)),
        ],
        false,
    );
    scalar(out, "compass", py_f64((90.0 + yaw).to_radians()), true);
    out.push_str("    }");
}

pub(super) fn write_metric_info_realistic(
    path: &Path,
    sim: &[SimFrame],
    layout: LargeLayout,
) -> std::io::Result<()> {
    let mut w = BufWriter::with_capacity(1 << 16, fs::File::create(path)?);
    let mut buf = String::with_capacity(2048);
    w.write_all(b"{\n")?;
    for (i, f) in sim.iter().enumerate() {
        buf.clear();
        if i > 0 {
            buf.push_str(",\n");
        }
        realistic_frame(&mut buf, i, f, layout);
        w.write_all(buf.as_bytes())?;
    }
    w.write_all(b"\n}")?;
    w.flush()?;
    Ok(())
}

/// A float as JSON (always with a decimal point, as Python writes floats).
fn fmt_f(x: f64) -> String {
    format!("{x:?}")
}
