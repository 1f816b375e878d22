//! A route's chunk timelines as small inline SVGs: which comfort chunks failed which bound, and
//! which lateral chunks were anomalous or critical (the monitor's per-chunk events). One path
//! per row (a 4,000-frame route has 200 chunks: one element per chunk would weigh on the page);
//! each row names its chunks in `data-chunks` and in its tooltip.

use std::fmt::Write;

use crate::route::events::BOUNDS;
use monitor_core::lateral::Band;

use crate::pipeline::timeline::ChunkLog;

const LABEL_W: u32 = 90;
const ROW_H: u32 = 12;
const MAX_W: u32 = 900;

/// Chunk width in px: the strip fits in `MAX_W`, between 1 and 12 px per chunk.
fn chunk_w(chunks: u32) -> f64 {
    (f64::from(MAX_W) / f64::from(chunks.max(1))).clamp(1.0, 12.0)
}

/// One row: its label, a grey track of `n` chunks, and the marked chunks as one path.
fn row(out: &mut String, y: u32, label: &str, n: u32, class: &str, color: &str, marked: &[u32]) {
    let w = chunk_w(n);
    let list = marked
        .iter()
        .map(u32::to_string)
        .collect::<Vec<_>>()
        .join(",");
    let _ = write!(
        out,
        "<text x=\"0\" y=\"{}\" fill=\"#555\">{label}</text><rect x=\"{LABEL_W}\" y=\"{}\" width=\"{:.1}\" height=\"{}\" fill=\"#eee\"/>",
        y + ROW_H - 3,
        y + 1,
        w * f64::from(n),
        ROW_H - 2
    );
    if marked.is_empty() {
        return;
    }
    let _ = write!(
        out,
        "<path class=\"{class}\" data-chunks=\"{list}\" fill=\"{color}\" d=\""
    );
    for &c in marked {
        let _ = write!(
            out,
            "M{:.1} {}h{:.1}v{}h{:.1}z",
            f64::from(LABEL_W) + w * f64::from(c),
            y + 1,
            w,
            ROW_H - 2,
            -w
        );
    }
    let _ = write!(out, "\"><title>{label}: chunk(s) {list}</title></path>");
}

fn open_svg(out: &mut String, n: u32, rows: u32) {
    let width = LABEL_W + (chunk_w(n) * f64::from(n)).ceil() as u32 + 2;
    let _ = write!(
        out,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width}\" height=\"{}\" font-family=\"sans-serif\" font-size=\"10\">",
        ROW_H * rows + 2
    );
}

/// The comfort chunks in which the car stood still for at least half of the frames, from the
/// route's stationary stretches (frame ranges `[start, end)`).
fn standing_chunks(stationary: &[(u32, u32)], chunks: u32, chunk_len: u16) -> Vec<u32> {
    let len = u32::from(chunk_len.max(1));
    (0..chunks)
        .filter(|k| {
            let (a, b) = (k * len, (k + 1) * len);
            let still: u32 = stationary
                .iter()
                .map(|&(s, e)| e.min(b).saturating_sub(s.max(a)))
                .sum();
            2 * still >= len
        })
        .collect()
}

/// The comfort timeline: a row of every failed chunk, one per bound, then the chunks the car
/// mostly stood through (comfortable by construction: §8.5's moving comfort leaves out the
/// chunks it did not drive).
pub(super) fn comfort(out: &mut String, log: &ChunkLog, chunk_len: u16, stationary: &[(u32, u32)]) {
    let n = log.comfort.len() as u32;
    let standing = standing_chunks(stationary, n, chunk_len);
    let failed: Vec<u32> = log
        .comfort
        .iter()
        .filter(|c| !c.failed.comfortable())
        .map(|c| c.chunk)
        .collect();
    let _ = write!(
        out,
        "<div class=\"timeline comfort\" data-chunks=\"{n}\" data-failed=\"{}\" data-standing=\"{}\"><b>Comfort</b>: {n} chunk(s) of {chunk_len} frames, {} failed (red: the chunk failed that bound), {} mostly standing (grey)",
        failed.len(),
        standing.len(),
        failed.len(),
        standing.len()
    );
    out.push('\n');
    if n > 0 {
        open_svg(out, n, 8);
        row(out, 0, "failed", n, "failed", "#e88", &failed);
        for (r, (name, test)) in BOUNDS.iter().enumerate() {
            let marked: Vec<u32> = log
                .comfort
                .iter()
                .filter(|c| test(&c.failed))
                .map(|c| c.chunk)
                .collect();
            let class = format!("fail-{name}");
            row(
                out,
                ROW_H * (r as u32 + 1),
                name,
                n,
                &class,
                "#c33",
                &marked,
            );
        }
        row(out, ROW_H * 7, "standing", n, "standing", "#999", &standing);
        out.push_str("</svg>");
    }
    out.push_str("</div>\n");
}

/// The lateral timeline: anomalous chunks (orange) and critical ones (red).
pub(super) fn lateral(out: &mut String, log: &ChunkLog, chunks: u32, chunk_len: u16) {
    let band = |b: Band| -> Vec<u32> {
        log.lateral
            .iter()
            .filter(|l| l.band == b)
            .map(|l| l.chunk)
            .collect()
    };
    let (anomalous, critical) = (band(Band::Anomalous), band(Band::Critical));
    let _ = write!(
        out,
        "<div class=\"timeline lateral\" data-chunks=\"{chunks}\" data-anomalous=\"{}\" data-critical=\"{}\"><b>Lateral excess</b>: {chunks} chunk(s) of {chunk_len} frames, {} anomalous (orange), {} critical (red)",
        anomalous.len(),
        critical.len(),
        anomalous.len(),
        critical.len()
    );
    out.push('\n');
    if chunks > 0 {
        open_svg(out, chunks, 2);
        row(out, 0, "anomalous", chunks, "anomalous", "#f90", &anomalous);
        row(
            out, ROW_H, "critical", chunks, "critical", "#c33", &critical,
        );
        out.push_str("</svg>");
    }
    out.push_str("</div>\n");
}
