//! The decomposition from DS to SDS (`docs/SCORE.md` "Decomposition") as a waterfall: DS, each
//! loss hanging from the running total, DS_safe, the loss to comfort, SDS. Drawn like the
//! collision figure ([`crate::report::figure`]): `plotters`' SVG backend, text as SVG `<text>`,
//! the same bytes on every run.

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::aggregate::decomposition::Decomposition;

/// Figure width, px.
pub const WIDTH: u32 = 720;
/// Figure height, px.
pub const HEIGHT: u32 = 360;

const TOTAL: RGBColor = RGBColor(31, 119, 180);
const LOSS: RGBColor = RGBColor(214, 39, 40);
const GAIN: RGBColor = RGBColor(44, 160, 44);
const FONT: &str = "sans-serif";

/// A rounding step smaller than this is left out of the picture (it would not show; the JSON
/// report has it).
const INVISIBLE: f64 = 0.005;

/// One bar: its label, where it starts and ends, and whether it is a total (from 0).
#[derive(Clone, Debug, PartialEq)]
pub struct Bar {
    /// Label under the bar.
    pub label: &'static str,
    /// Value at the bar's top before the step (0 for a total).
    pub from: f64,
    /// Value after the step.
    pub to: f64,
    /// A total (DS, DS_safe, SDS) rather than a step.
    pub total: bool,
}

/// The bars of a decomposition, left to right; the comfort step and SDS only when comfort is
/// defined.
///
/// ```
/// use monitor_host::aggregate::decomposition::Decomposition;
/// use monitor_host::route::decomposition::Losses;
/// let d = Decomposition::of(70.0, Losses { nodecel: 10.0, ..Losses::default() }, 60.0, Some(0.5));
/// let bars = monitor_host::report::waterfall::bars(&d);
/// let labels: Vec<_> = bars.iter().map(|b| b.label).collect();
/// assert_eq!(labels, ["DS", "work zone", "no decel.", "lat. anomalous", "lat. critical",
///     "DS_safe", "comfort", "SDS"]);
/// assert_eq!((bars[2].from, bars[2].to), (70.0, 60.0));
/// ```
pub fn bars(d: &Decomposition) -> Vec<Bar> {
    let total = |label, v| Bar {
        label,
        from: 0.0,
        to: v,
        total: true,
    };
    let mut out = vec![total("DS", d.ds)];
    let mut cur = d.ds;
    let l = &d.losses;
    let steps = [
        ("rounding", l.rounding),
        ("work zone", l.workzone),
        ("no decel.", l.nodecel),
        ("lat. anomalous", l.anomalous),
        ("lat. critical", l.critical),
    ];
    for (label, loss) in steps {
        if label == "rounding" && loss.abs() < INVISIBLE {
            continue;
        }
        out.push(Bar {
            label,
            from: cur,
            to: cur - loss,
            total: false,
        });
        cur -= loss;
    }
    out.push(total("DS_safe", d.ds_safe));
    if let (Some(c), Some(sds)) = (d.comfort, d.sds) {
        out.push(Bar {
            label: "comfort",
            from: d.ds_safe,
            to: d.ds_safe - c,
            total: false,
        });
        out.push(total("SDS", sds));
    }
    out
}

/// Renders the waterfall as an SVG document.
///
/// ```
/// use monitor_host::aggregate::decomposition::Decomposition;
/// use monitor_host::route::decomposition::Losses;
/// let d = Decomposition::of(70.0, Losses { nodecel: 10.0, ..Losses::default() }, 60.0, Some(0.5));
/// let svg = monitor_host::report::waterfall::svg(&d);
/// assert!(svg.starts_with("<svg") && svg.contains("SDS") && svg.contains("−10.00"));
/// ```
pub fn svg(d: &Decomposition) -> String {
    crate::report::figure::render_svg((WIDTH, HEIGHT), |root| draw(root, d))
}

fn draw(
    root: &DrawingArea<SVGBackend<'_>, plotters::coord::Shift>,
    d: &Decomposition,
) -> Result<(), DrawingAreaErrorKind<std::io::Error>> {
    root.fill(&WHITE)?;
    let bars = bars(d);
    let area = root.titled(
        "From DS to SDS: where the points went",
        (FONT, 17).into_font().color(&BLACK),
    )?;
    let top = bars.iter().map(|b| b.from.max(b.to)).fold(1.0f64, f64::max) * 1.12;
    let bottom = bars.iter().map(|b| b.from.min(b.to)).fold(0.0f64, f64::min);
    let n = bars.len() as f64;
    let mut chart = ChartBuilder::on(&area)
        .margin(8)
        .margin_right(20)
        .x_label_area_size(28)
        .y_label_area_size(48)
        .build_cartesian_2d(0.0..n, bottom..top)?;
    chart
        .configure_mesh()
        .light_line_style(WHITE.mix(0.0))
        .bold_line_style(BLACK.mix(0.08))
        .disable_x_mesh()
        .x_labels(0)
        .x_label_formatter(&|_| String::new())
        .y_desc("score")
        .label_style((FONT, 12))
        .axis_desc_style((FONT, 13))
        .draw()?;
    let value = (FONT, 11)
        .into_font()
        .color(&BLACK)
        .pos(Pos::new(HPos::Center, VPos::Bottom));
    let label = (FONT, 12)
        .into_font()
        .color(&BLACK)
        .pos(Pos::new(HPos::Center, VPos::Top));
    for (i, b) in bars.iter().enumerate() {
        let x = i as f64;
        let colour = if b.total {
            TOTAL
        } else if b.to <= b.from {
            LOSS
        } else {
            GAIN
        };
        chart.draw_series(std::iter::once(Rectangle::new(
            [(x + 0.15, b.from), (x + 0.85, b.to)],
            colour.filled(),
        )))?;
        let text = if b.total {
            format!("{:.2}", b.to)
        } else {
            format!("−{:.2}", b.from - b.to)
        };
        chart.draw_series(std::iter::once(Text::new(
            text,
            (x + 0.5, b.from.max(b.to)),
            value.clone(),
        )))?;
        // Labels under the axis, in pixels (the x axis has no numbers).
        let (px, py) = chart.backend_coord(&(x + 0.5, bottom));
        root.draw(&Text::new(b.label, (px, py + 6), label.clone()))?;
        if i + 1 < bars.len() {
            // The connector from this bar's end to the next bar.
            chart.draw_series(std::iter::once(PathElement::new(
                [(x + 0.85, b.to), (x + 1.15, b.to)],
                BLACK.mix(0.4).stroke_width(1),
            )))?;
        }
    }
    if d.comfort.is_none() {
        let note = (FONT, 12)
            .into_font()
            .color(&RGBColor(120, 120, 120))
            .pos(Pos::new(HPos::Right, VPos::Top));
        root.draw(&Text::new(
            "comfort undefined (no telemetry): no SDS",
            (WIDTH as i32 - 24, 30),
            note,
        ))?;
    }
    Ok(())
}
