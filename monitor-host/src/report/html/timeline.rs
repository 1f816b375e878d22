//! A route's chunk timelines as small inline SVGs: which comfort chunks failed which bound, and
//! which lateral chunks were anomalous or critical (the monitor's per-chunk events).

use std::fmt::Write;

use monitor_core::lateral::Band;

use crate::pipeline::timeline::ChunkLog;

const LABEL_W: u32 = 90;
const ROW_H: u32 = 12;
const MAX_W: u32 = 900;

/// Chunk width in px: the strip fits in `MAX_W`, between 1 and 12 px per chunk.
fn chunk_w(chunks: u32) -> f64 {
    (f64::from(MAX_W) / f64::from(chunks.max(1))).clamp(1.0, 12.0)
}

/// The comfort timeline: one row per bound, a mark per chunk that failed it; a top row with
/// every chunk, green when comfortable.
pub(super) fn comfort(out: &mut String, log: &ChunkLog, chunk_len: u16) {
    let n = log.comfort.len() as u32;
    let failed = log
        .comfort
        .iter()
        .filter(|c| !c.failed.comfortable())
        .count();
    let _ = write!(
        out,
        "<div class=\"timeline comfort\" data-chunks=\"{n}\" data-failed=\"{failed}\"><b>Comfort</b>: {n} chunk(s) of {chunk_len} frames, {failed} failed\n"
    );
    if n == 0 {
        out.push_str("</div>\n");
        return;
    }
    let w = chunk_w(n);
    let rows: [(&str, fn(&monitor_core::Failures) -> bool); 6] = [
        ("lon_acc", |f| f.lon_acc),
        ("lat_acc", |f| f.lat_acc),
        ("mag_jerk", |f| f.mag_jerk),
        ("lon_jerk", |f| f.lon_jerk),
        ("yaw_acc", |f| f.yaw_acc),
        ("yaw_rate", |f| f.yaw_rate),
    ];
    let width = LABEL_W + (w * f64::from(n)).ceil() as u32 + 2;
    let height = ROW_H * 7 + 2;
    let _ = write!(
        out,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width}\" height=\"{height}\" font-family=\"sans-serif\" font-size=\"10\">"
    );
    row_label(out, 0, "chunks");
    for c in &log.comfort {
        let ok = c.failed.comfortable();
        let _ = write!(
            out,
            "<rect x=\"{:.1}\" y=\"1\" width=\"{:.1}\" height=\"{}\" fill=\"{}\"><title>chunk {}: {}</title></rect>",
            f64::from(LABEL_W) + w * f64::from(c.chunk),
            w,
            ROW_H - 2,
            if ok { "#8c8" } else { "#e88" },
            c.chunk,
            if ok { "comfortable" } else { "failed" }
        );
    }
    for (r, (name, test)) in rows.iter().enumerate() {
        let y = ROW_H * (r as u32 + 1);
        row_label(out, y, name);
        for c in log.comfort.iter().filter(|c| test(&c.failed)) {
            let _ = write!(
                out,
                "<rect class=\"fail-{name}\" x=\"{:.1}\" y=\"{}\" width=\"{:.1}\" height=\"{}\" fill=\"#c33\"><title>chunk {} failed {name}</title></rect>",
                f64::from(LABEL_W) + w * f64::from(c.chunk),
                y + 1,
                w,
                ROW_H - 2,
                c.chunk
            );
        }
    }
    out.push_str("</svg></div>\n");
}

/// The lateral timeline: every chunk, orange when anomalous, red when critical.
pub(super) fn lateral(out: &mut String, log: &ChunkLog, chunks: u32, chunk_len: u16) {
    let anomalous = log
        .lateral
        .iter()
        .filter(|l| l.band == Band::Anomalous)
        .count();
    let critical = log
        .lateral
        .iter()
        .filter(|l| l.band == Band::Critical)
        .count();
    let _ = write!(
        out,
        "<div class=\"timeline lateral\" data-chunks=\"{chunks}\" data-anomalous=\"{anomalous}\" data-critical=\"{critical}\"><b>Lateral excess</b>: {chunks} chunk(s) of {chunk_len} frames, {anomalous} anomalous, {critical} critical\n"
    );
    if chunks == 0 {
        out.push_str("</div>\n");
        return;
    }
    let w = chunk_w(chunks);
    let width = LABEL_W + (w * f64::from(chunks)).ceil() as u32 + 2;
    let _ = write!(
        out,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width}\" height=\"{}\" font-family=\"sans-serif\" font-size=\"10\">",
        ROW_H + 2
    );
    row_label(out, 0, "excess");
    let _ = write!(
        out,
        "<rect x=\"{LABEL_W}\" y=\"1\" width=\"{:.1}\" height=\"{}\" fill=\"#ddd\"/>",
        w * f64::from(chunks),
        ROW_H - 2
    );
    for l in &log.lateral {
        let (class, color) = match l.band {
            Band::Critical => ("critical", "#c33"),
            _ => ("anomalous", "#f90"),
        };
        let _ = write!(
            out,
            "<rect class=\"{class}\" x=\"{:.1}\" y=\"1\" width=\"{:.1}\" height=\"{}\" fill=\"{color}\"><title>chunk {}: {class}, max excess {:.2} m</title></rect>",
            f64::from(LABEL_W) + w * f64::from(l.chunk),
            w,
            ROW_H - 2,
            l.chunk,
            l.max_excess
        );
    }
    out.push_str("</svg></div>\n");
}

fn row_label(out: &mut String, y: u32, name: &str) {
    let _ = write!(
        out,
        "<text x=\"0\" y=\"{}\" fill=\"#555\">{name}</text>",
        y + ROW_H - 3
    );
}
