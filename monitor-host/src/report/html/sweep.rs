//! The sweep on the comparison page (`sds compare --sweep`, docs/SCORE.md §10.4): each model's rank by SDS
//! at every point of the grid, one line per model (rank 1 at the top), so a reader sees at a
//! glance whether the lines cross; each point's settings under the axis, each dot's SDS in its
//! tooltip.
//!
//! Hand-written SVG: the same comparison gives the same bytes, and every name from the user
//! goes through [`escape`].

use super::page::escape;
use crate::stats::Comparison;

/// Width of one point's column, px.
const COL: f64 = 44.0;
/// The figure's left margin (the rank axis), px.
const LEFT: f64 = 40.0;
/// Height of one rank's row, px.
const ROW: f64 = 28.0;
/// The lines' colours, one per model in order (repeating after eight).
const COLOURS: [&str; 8] = [
    "#1f5fbf", "#d07a00", "#2e8b57", "#b22222", "#6a3d9a", "#8c564b", "#e377c2", "#555555",
];

/// The section, or nothing without a sweep.
///
/// ```
/// use monitor_host::report::html::sweep::section;
/// use monitor_host::settings::defs::Value;
/// use monitor_host::stats::sweep::report;
/// use monitor_host::stats::{compare, CompareOptions, Model, NamedRun};
/// use monitor_host::{demo, score_run, Inputs, Settings};
/// let dir = tempfile::tempdir()?;
/// let run = demo::write(dir.path())?;
/// let r = score_run(&Inputs::new([run.results]), &Settings { allow_missing_telemetry: true, ..Settings::default() })?;
/// let m = |n: &str| Model { name: n.into(), runs: vec![NamedRun { name: n.into(), report: r.clone() }] };
/// let mut c = compare(&[m("a"), m("b")], &CompareOptions::default())?;
/// assert_eq!(section(&c), "");
/// let at = |v: f32| vec![("slack".to_string(), Value::F32(v))];
/// c.sweep = Some(report(&["slack".into()], &["a".into(), "b".into()], vec![
///     (at(0.7), vec![[None, None, Some(50.0)], [None, None, Some(40.0)]]),
///     (at(0.9), vec![[None, None, Some(40.0)], [None, None, Some(50.0)]]),
/// ]));
/// let html = section(&c);
/// assert!(html.contains("id=\"sweep\"") && html.contains("a: rank 2, SDS 40.00"));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn section(c: &Comparison) -> String {
    let Some(s) = &c.sweep else {
        return String::new();
    };
    let models: Vec<&str> = s
        .points
        .first()
        .map(|p| p.models.iter().map(|m| m.model.as_str()).collect())
        .unwrap_or_default();
    let (n, points) = (models.len().max(1), s.points.len());
    let top = 24.0;
    let y = |r: usize| top + (r as f64 - 1.0) * ROW;
    let x = |i: usize| LEFT + COL * (i as f64 + 0.5);
    let axis = y(n) + 18.0;
    let width = LEFT + COL * points.max(1) as f64 + 140.0;
    let height = axis + 24.0;
    let mut svg = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width:.0}\" height=\"{height:.0}\" viewBox=\"0 0 {width:.0} {height:.0}\" font-family=\"sans-serif\" font-size=\"11\">\n<text x=\"4\" y=\"{:.1}\">rank</text>\n",
        top - 10.0
    );
    for r in 1..=n {
        svg.push_str(&format!(
            "<line x1=\"{LEFT}\" y1=\"{0:.1}\" x2=\"{1:.1}\" y2=\"{0:.1}\" stroke=\"#eee\"/><text x=\"{2:.1}\" y=\"{3:.1}\" text-anchor=\"end\">{r}</text>\n",
            y(r),
            LEFT + COL * points as f64,
            LEFT - 6.0,
            y(r) + 4.0
        ));
    }
    for i in 0..points {
        svg.push_str(&format!(
            "<text x=\"{:.1}\" y=\"{axis:.1}\" text-anchor=\"middle\">{i}</text>\n",
            x(i)
        ));
    }
    svg.push_str(&format!(
        "<text x=\"{LEFT}\" y=\"{:.1}\" fill=\"#666\" font-size=\"9\">point (settings listed below)</text>\n",
        axis + 16.0
    ));
    for (k, name) in models.iter().enumerate() {
        let colour = COLOURS[k % COLOURS.len()];
        let name = escape(name);
        let ranks: Vec<Option<(usize, f64)>> = s
            .points
            .iter()
            .map(|p| {
                let m = p.models.get(k)?;
                Some((m.rank?, m.sds?))
            })
            .collect();
        // One line per run of consecutive points with a rank (a point without SDS breaks it).
        let mut segment: Vec<String> = Vec::new();
        let mut segments: Vec<Vec<String>> = Vec::new();
        for (i, r) in ranks.iter().enumerate() {
            match r {
                Some((rank, _)) => segment.push(format!("{:.1},{:.1}", x(i), y(*rank))),
                None => segments.push(std::mem::take(&mut segment)),
            }
        }
        segments.push(segment);
        for seg in segments.iter().filter(|s| s.len() > 1) {
            svg.push_str(&format!(
                "<polyline points=\"{}\" fill=\"none\" stroke=\"{colour}\" stroke-width=\"2\" opacity=\"0.8\"/>\n",
                seg.join(" ")
            ));
        }
        for (i, r) in ranks.iter().enumerate() {
            if let Some((rank, sds)) = r {
                svg.push_str(&format!(
                    "<circle cx=\"{:.1}\" cy=\"{:.1}\" r=\"4\" fill=\"{colour}\"><title>point {i}: {name}: rank {rank}, SDS {sds:.2}</title></circle>\n",
                    x(i),
                    y(*rank)
                ));
            }
        }
        // The legend, right of the plot.
        let ly = top + k as f64 * 16.0;
        let lx = LEFT + COL * points as f64 + 16.0;
        svg.push_str(&format!(
            "<line x1=\"{lx:.1}\" y1=\"{ly:.1}\" x2=\"{:.1}\" y2=\"{ly:.1}\" stroke=\"{colour}\" stroke-width=\"2\"/><text x=\"{:.1}\" y=\"{:.1}\">{name}</text>\n",
            lx + 18.0,
            lx + 24.0,
            ly + 4.0
        ));
    }
    svg.push_str("</svg>");
    let key: Vec<String> = s
        .points
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let v: Vec<String> = p
                .values
                .iter()
                .map(|(k, v)| format!("{}={}", escape(k), escape(&v.text())))
                .collect();
            format!("{i}: {}", v.join(", "))
        })
        .collect();
    let unstable: Vec<String> = s
        .pairs
        .iter()
        .filter(|p| !p.order_stable)
        .map(|p| format!("{} / {}", escape(&p.a), escape(&p.b)))
        .collect();
    let verdict = if unstable.is_empty() {
        "every pair of models keeps its order at every point".to_string()
    } else {
        format!(
            "the order changes over the grid for: {}",
            unstable.join("; ")
        )
    };
    format!(
        "<h2 id=\"sweep\">Sweep</h2>\n<p class=\"note\">each model's rank by SDS at every point of the grid (rank 1 at the top; 1 + the models with a strictly greater SDS); lines that cross are conclusions that depend on the settings; {verdict}</p>\n<div class=\"fig wide\">{svg}</div>\n<p class=\"note\">{}</p>\n",
        key.join("; ")
    )
}
