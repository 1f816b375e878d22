//! A route's timelines as small inline SVGs: every event on the frame axis ([`events`]), which
//! comfort chunks failed which bound, and which lateral chunks were anomalous or critical (the
//! monitor's per-chunk events). One path
//! per row (a 4,000-frame route has 200 chunks: one element per chunk would weigh on the page);
//! each row names its chunks in `data-chunks` and in its tooltip.

use std::fmt::Write;

use crate::route::events::BOUNDS;
use monitor_core::lateral::Band;

use crate::pipeline::timeline::ChunkLog;
use crate::route::events::RouteEvent;
use crate::route::row::RouteReport;

use super::page::escape;

const LABEL_W: u32 = 90;
const ROW_H: u32 = 12;
const MAX_W: u32 = 900;

/// The most collision figures drawn in the page for one route (100,000 collisions made a
/// 1.09 GB page); the others are counted under them, and every collision is in the JSON report.
pub const FIGURES_PER_ROUTE: usize = 10;

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
/// mostly stood through (comfortable by construction: docs/SCORE.md §10.0's moving comfort leaves out the
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

/// The rows of the events timeline: (label, the kinds drawn in it).
const EVENT_ROWS: [(&str, &[&str]); 5] = [
    ("collisions", &["collision"]),
    (
        "infractions",
        &[
            "red_light",
            "stop_sign",
            "blocked",
            "route_deviation",
            "outside_lanes",
            "min_speed",
            "yield_emergency_vehicle",
            "scenario_timeout",
            "route_timeout",
            "other",
        ],
    ),
    ("lateral", &["lateral_anomalous", "lateral_critical"]),
    ("comfort", &["uncomfortable"]),
    ("standing", &["stationary"]),
];

/// A marker's colour by kind.
fn event_color(kind: &str) -> &'static str {
    match kind {
        "collision" | "lateral_critical" | "red_light" => "#c33",
        "stop_sign" => "#a0c",
        "lateral_anomalous" => "#f90",
        "uncomfortable" => "#e88",
        "stationary" => "#999",
        "blocked" | "route_deviation" => "#36c",
        _ => "#777",
    }
}

/// A route's events on one frame axis (issue 28): a row per family (collisions, the evaluator's
/// other infractions, lateral chunks, uncomfortable chunks, stationary stretches); an event at a
/// frame is a dot, a chunk or stretch a bar; each names its kind, list, frame, time and message
/// on hover, and a collision with a figure links to it (`#route-<i>-collision-<k>`). Frame `f`
/// of `frames` sits at `x0 + f × w / (frames − 1)` on the axis (`class="axis"`); the page's
/// script measures each marker back to a frame (`data-at-frame`, the browser test). Events
/// that could not be placed are listed below it, never dropped.
pub(super) fn events(out: &mut String, r: &RouteReport, route: usize) {
    let frames = r.frames as usize;
    let (placed, unplaced): (Vec<&RouteEvent>, Vec<&RouteEvent>) = r
        .events
        .iter()
        .partition(|e| e.frame.is_some_and(|f| f < frames));
    let figures: Vec<usize> = r
        .traces
        .iter()
        .take(FIGURES_PER_ROUTE)
        .map(|t| t.event)
        .collect();
    let _ = write!(
        out,
        "<div class=\"timeline events\" data-frames=\"{frames}\" data-placed=\"{}\" data-unplaced=\"{}\"><b>Events</b>: {} on the route's {frames} frames, {} not placed",
        placed.len(),
        unplaced.len(),
        placed.len(),
        unplaced.len()
    );
    out.push('\n');
    if frames > 0 {
        let w = f64::from(MAX_W);
        let scale = w / (frames.saturating_sub(1).max(1)) as f64;
        let x = |f: usize| f64::from(LABEL_W) + f as f64 * scale;
        let rows = EVENT_ROWS.len() as u32;
        let height = ROW_H * (rows + 1) + 4;
        let _ = write!(
            out,
            "<svg class=\"events-axis\" data-frames=\"{frames}\" xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{height}\" font-family=\"sans-serif\" font-size=\"10\">",
            LABEL_W + MAX_W + 8
        );
        for (i, (label, _)) in EVENT_ROWS.iter().enumerate() {
            let y = ROW_H * i as u32;
            let _ = write!(
                out,
                "<text x=\"0\" y=\"{}\" fill=\"#555\">{label}</text><rect x=\"{LABEL_W}\" y=\"{}\" width=\"{MAX_W}\" height=\"{}\" fill=\"#f3f3f3\"/>",
                y + ROW_H - 3,
                y + 1,
                ROW_H - 2
            );
        }
        // The frame axis, with the first, last and three frames between labelled.
        let axis_y = ROW_H * rows + 2;
        let _ = write!(
            out,
            "<line class=\"axis\" x1=\"{LABEL_W}\" y1=\"{axis_y}\" x2=\"{}\" y2=\"{axis_y}\" stroke=\"#888\"/>",
            LABEL_W + MAX_W
        );
        let mut ticks: Vec<usize> = (0..=4).map(|k| (frames - 1) * k / 4).collect();
        ticks.dedup();
        let last = ticks.len() - 1;
        for (k, f) in ticks.into_iter().enumerate() {
            let anchor = match k {
                0 => "start",
                k if k == last => "end",
                _ => "middle",
            };
            let _ = write!(
                out,
                "<text x=\"{:.1}\" y=\"{}\" fill=\"#888\" text-anchor=\"{anchor}\">frame {f}</text>",
                x(f),
                axis_y + ROW_H - 2
            );
        }
        for e in placed.iter().take(MARKERS_PER_ROUTE) {
            let Some(row) = EVENT_ROWS
                .iter()
                .position(|(_, kinds)| kinds.contains(&e.kind))
            else {
                continue;
            };
            let f = e.frame.unwrap_or_default();
            let y = ROW_H * row as u32;
            let title = format!(
                "{}{} at frame {f}{}: {}",
                e.kind,
                e.list
                    .as_deref()
                    .map_or(String::new(), |l| format!(" ({l})")),
                e.time_s
                    .map_or(String::new(), |t| format!(", t = {t:.2} s")),
                e.message
            );
            let attrs = format!(
                "class=\"ev ev-{}\" data-kind=\"{}\" data-frame=\"{f}\" fill=\"{}\"",
                e.kind,
                e.kind,
                event_color(e.kind)
            );
            let link = e
                .collision
                .filter(|c| figures.contains(c))
                .map(|c| format!("#route-{route}-collision-{c}"));
            if let Some(href) = &link {
                let _ = write!(out, "<a href=\"{href}\">");
            }
            match e.end_frame {
                Some(end) if end > f => {
                    let _ = write!(
                        out,
                        "<rect {attrs} data-end-frame=\"{end}\" x=\"{:.1}\" y=\"{}\" width=\"{:.1}\" height=\"{}\"><title>{}</title></rect>",
                        x(f),
                        y + 2,
                        // Clamped to the axis: a stretch to the end ends at the last frame.
                        (x(end.min(frames - 1)) - x(f)).max(1.0),
                        ROW_H - 4,
                        escape(&title)
                    );
                }
                _ => {
                    let _ = write!(
                        out,
                        "<circle {attrs} cx=\"{:.1}\" cy=\"{}\" r=\"4\" stroke=\"#fff\"><title>{}</title></circle>",
                        x(f),
                        y + ROW_H / 2,
                        escape(&title)
                    );
                }
            }
            if link.is_some() {
                out.push_str("</a>");
            }
        }
        out.push_str("</svg>");
        more(out, placed.len(), "placed event(s) without a marker");
    }
    if !unplaced.is_empty() {
        out.push_str("<ul class=\"unplaced\">");
        for e in unplaced.iter().take(MARKERS_PER_ROUTE) {
            // Most messages already say why ("(not placed: no telemetry)"): say it once.
            let prefix = if e.message.contains("(not placed: ") {
                ""
            } else {
                "not placed: "
            };
            let _ = write!(
                out,
                "<li data-kind=\"{}\">{prefix}{}</li>",
                e.kind,
                escape(&e.message)
            );
        }
        out.push_str("</ul>");
        more(out, unplaced.len(), "event(s) not placed and not listed");
    }
    out.push_str("</div>\n");
}

/// The most markers drawn on a route's events axis, and the most unplaced events listed under
/// it (100,000 collisions made a 1.09 GB page and 2.5 GB of memory); the first by frame are
/// drawn, the rest counted, and every event is in the JSON report's `events`.
pub const MARKERS_PER_ROUTE: usize = 500;

/// The count of events left out when there are more than [`MARKERS_PER_ROUTE`].
fn more(out: &mut String, n: usize, what: &str) {
    if n > MARKERS_PER_ROUTE {
        let _ = write!(
            out,
            "<p class=\"note more-events\">and {} more {what} (at most {MARKERS_PER_ROUTE} per \
             route; every event is in the JSON report's events)</p>",
            n - MARKERS_PER_ROUTE
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::route_set::MissingRoute;
    use crate::route::row::missing_report;

    fn event(kind: &'static str, frame: Option<usize>, message: &str) -> RouteEvent {
        RouteEvent {
            kind,
            list: Some("red_light".into()),
            frame,
            end_frame: None,
            step: frame.map(|f| f as u64),
            time_s: frame.map(|f| f as f64 * 0.05),
            placed_by: frame.map(|_| "closest_approach"),
            distance_m: None,
            collision: None,
            message: message.into(),
        }
    }

    fn route(frames: u32, events: Vec<RouteEvent>) -> RouteReport {
        let mut r = missing_report(&MissingRoute {
            route_id: "RouteScenario_1_rep0".into(),
            xml_id: "1".into(),
            town: None,
            scenario_type: None,
        });
        r.frames = frames;
        r.events = events;
        r
    }

    #[test]
    fn markers_sit_on_the_frame_axis_and_unplaced_are_listed() {
        let mut out = String::new();
        let r = route(
            101,
            vec![
                event("red_light", Some(50), "ran <it>"),
                event("red_light", None, "ran (not placed: no position)"),
            ],
        );
        events(&mut out, &r, 3);
        // Frame 50 of 101: half way along the axis.
        let cx = f64::from(LABEL_W) + 50.0 * f64::from(MAX_W) / 100.0;
        assert!(
            out.contains(&format!("data-frame=\"50\" fill=\"#c33\" cx=\"{cx:.1}\"")),
            "{out}"
        );
        assert!(out.contains("ran &lt;it&gt;") && !out.contains("ran <it>"));
        assert!(out.contains("<li data-kind=\"red_light\">ran (not placed: no position)</li>"));
        assert!(out.contains("data-placed=\"1\" data-unplaced=\"1\""));
    }

    #[test]
    fn a_one_frame_route_has_one_tick_and_no_frames_no_axis() {
        let mut out = String::new();
        events(
            &mut out,
            &route(1, vec![event("red_light", Some(0), "x")]),
            0,
        );
        assert_eq!(out.matches(">frame 0</text>").count(), 1, "{out}");
        let mut out = String::new();
        events(
            &mut out,
            &route(0, vec![event("red_light", Some(0), "x")]),
            0,
        );
        assert!(
            !out.contains("<svg") && out.contains("not placed: x"),
            "{out}"
        );
    }
}
