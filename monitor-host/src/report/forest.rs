//! The comparison's forest plot (`sds compare --format html`, docs/SCORE.md §10.3): per metric
//! a panel, per model a row with its delta against the baseline (a dot) and its 95 % interval
//! (a bar), and the line of no difference. Green: better, red: worse, grey: within noise; a row
//! without a compared route says `no data` (so an empty panel says why it is empty).
//!
//! Drawn with `plotters`' SVG backend, as the collision figures ([`crate::report::figure`]):
//! no font is loaded, and the same comparison gives the same bytes. Model names come from the
//! user and are shown through [`printable`], as in every other output.

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::report::escape::printable;
use crate::stats::bootstrap::Verdict;
use crate::stats::Comparison;

const FONT: &str = "sans-serif";
const BETTER: RGBColor = RGBColor(42, 160, 90);
const WORSE: RGBColor = RGBColor(200, 40, 40);
const NOISE: RGBColor = RGBColor(110, 110, 110);
/// Height of one model's row, px.
const ROW: u32 = 34;
/// Width of one metric's panel, px.
const PANEL: u32 = 300;

/// The forest plot as an SVG document (`no data` in the rows where nothing could be compared).
///
/// ```
/// use monitor_host::stats::{compare, CompareOptions, Model, NamedRun};
/// use monitor_host::{demo, score_run, Inputs, Settings};
/// let dir = tempfile::tempdir()?;
/// let run = demo::write(dir.path())?;
/// let inputs = Inputs { telemetry: Some(run.telemetry), ..Inputs::new([run.results]) };
/// let report = score_run(&inputs, &Settings::default())?;
/// let m = |n: &str| Model { name: n.into(), runs: vec![NamedRun { name: n.into(), report: report.clone() }] };
/// let c = compare(&[m("base"), m("new")], &CompareOptions::default())?;
/// let svg = monitor_host::report::forest::svg(&c);
/// assert!(svg.starts_with("<svg") && svg.contains("ds_safe") && svg.contains("new"));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn svg(c: &Comparison) -> String {
    let models: Vec<&str> = c
        .models
        .iter()
        .map(|m| m.name.as_str())
        .filter(|m| *m != c.baseline)
        .collect();
    // The labels as every output shows them: control and bidirectional characters escaped.
    let labels: Vec<String> = models.iter().map(|m| printable(m).into_owned()).collect();
    let width = PANEL * c.metrics.len() as u32;
    let height = 90 + ROW * models.len().max(1) as u32;
    crate::report::figure::render_svg((width, height), |root| draw(root, c, &models, &labels))
}

fn draw(
    root: &DrawingArea<SVGBackend<'_>, plotters::coord::Shift>,
    c: &Comparison,
    models: &[&str],
    labels: &[String],
) -> Result<(), DrawingAreaErrorKind<std::io::Error>> {
    root.fill(&WHITE)?;
    let panels = root.split_evenly((1, c.metrics.len()));
    let k = models.len().max(1) as f64;
    for (i, (panel, metric)) in panels.iter().zip(&c.metrics).enumerate() {
        let rows: Vec<(usize, f64, [f64; 2], Option<Verdict>)> = models
            .iter()
            .enumerate()
            .filter_map(|(j, m)| {
                let p = c
                    .paired
                    .iter()
                    .find(|p| p.model == *m && p.metric == *metric)?;
                Some((j, p.result.delta?, p.result.ci95?, p.result.verdict))
            })
            .collect();
        // The rows without an interval: no route was compared (n = 0).
        let empty: Vec<usize> = (0..models.len())
            .filter(|j| !rows.iter().any(|r| r.0 == *j))
            .collect();
        let (mut lo, mut hi) = (0.0f64, 0.0f64);
        for (_, d, [a, b], _) in &rows {
            lo = lo.min(*a).min(*d);
            hi = hi.max(*b).max(*d);
        }
        // A fraction-valued metric (success, comfort) gets a narrower empty range than a score.
        let unit = if *metric == "success" || *metric == "comfort" {
            0.05
        } else {
            1.0
        };
        let pad = ((hi - lo) * 0.1).max(if hi > lo { 0.0 } else { unit });
        let digits = if unit < 1.0 { 3 } else { 1 };
        let longest = labels.iter().map(|m| m.chars().count()).max().unwrap_or(1) as u32;
        let y_area = if i == 0 {
            (12 + 7 * longest).min(160)
        } else {
            10
        };
        let mut chart = ChartBuilder::on(panel)
            .caption(format!("Δ {metric}"), (FONT, 15))
            .margin(8)
            .x_label_area_size(30)
            .y_label_area_size(y_area)
            .build_cartesian_2d(lo - pad..hi + pad, -0.5..k - 0.5)?;
        let names = labels;
        chart
            .configure_mesh()
            .disable_y_mesh()
            .light_line_style(WHITE.mix(0.0))
            .bold_line_style(BLACK.mix(0.08))
            .x_labels(5)
            .y_labels(models.len().max(1))
            .x_label_formatter(&|v| format!("{v:.digits$}"))
            .y_label_formatter(&|v| {
                let j = v.round();
                if i == 0 && (v - j).abs() < 1e-6 && j >= 0.0 {
                    names
                        .get(j as usize)
                        .map_or(String::new(), |s| s.to_string())
                } else {
                    String::new()
                }
            })
            .label_style((FONT, 12))
            .y_label_style((FONT, 13))
            .draw()?;
        chart.draw_series(DashedLineSeries::new(
            [(0.0, -0.5), (0.0, k - 0.5)],
            5,
            4,
            BLACK.mix(0.5).stroke_width(1),
        ))?;
        for j in empty {
            chart.draw_series(std::iter::once(Text::new(
                "no data (n = 0)",
                ((lo + hi) / 2.0, j as f64),
                (FONT, 13)
                    .into_font()
                    .color(&NOISE)
                    .pos(Pos::new(HPos::Center, VPos::Center)),
            )))?;
        }
        for (j, d, [a, b], v) in rows {
            let color = match v {
                Some(Verdict::Better) => BETTER,
                Some(Verdict::Worse) => WORSE,
                _ => NOISE,
            };
            let y = j as f64;
            chart.draw_series(std::iter::once(PathElement::new(
                vec![(a, y), (b, y)],
                color.stroke_width(3),
            )))?;
            chart.draw_series(std::iter::once(Circle::new((d, y), 5, color.filled())))?;
        }
    }
    Ok(())
}
