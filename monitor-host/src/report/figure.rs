//! The collision figure (docs/SCORE.md §14.4, the paper's Figure 2): one SVG of a
//! [`CollisionTrace`], two panels sharing the time axis (speed in km/h above, raw `a_lon` in
//! m/s² below), the collision instant, the deceleration window shaded, the threshold, and the
//! verdict, route, object and impact speed in the title.
//!
//! Drawn with `plotters`' SVG backend only: text is written as SVG `<text>` (no font is loaded),
//! and nothing depends on the machine or the clock, so the bytes are the same on every run.

use plotters::prelude::*;

use crate::report::escape::printable;
use crate::route::trace::{CollisionTrace, Verdict, AFTER_S, BEFORE_S};

/// Figure width, px.
pub const WIDTH: u32 = 720;
/// Figure height, px.
pub const HEIGHT: u32 = 480;

const SPEED: RGBColor = RGBColor(31, 119, 180);
const ACC: RGBColor = RGBColor(44, 44, 44);
const IMPACT: RGBColor = RGBColor(214, 39, 40);
const WINDOW: RGBColor = RGBColor(255, 191, 0);
const THRESHOLD: RGBColor = RGBColor(120, 120, 120);
const FONT: &str = "sans-serif";

/// m/s → km/h.
const KMH: f64 = 3.6;

/// The figure's title: verdict, route, object and impact speed.
///
/// ```
/// # use monitor_host::route::trace::{CollisionTrace, Verdict};
/// let t = CollisionTrace { route_id: "RouteScenario_1_rep0".into(), event: 0,
///     list: "collisions_vehicle", type_id: Some("vehicle.audi.tt".into()), frame: 90,
///     time_s: 4.5, impact_speed: 5.0, verdict: Verdict::NoDeceleration, window: None,
///     threshold: -0.5, points: vec![] };
/// assert_eq!(monitor_host::report::figure::title(&t),
///     "RouteScenario_1_rep0: no deceleration · vehicle.audi.tt at 18.0 km/h");
/// ```
pub fn title(t: &CollisionTrace) -> String {
    // The id and type come from the inputs: a control character would make the SVG malformed
    // XML, a bidi override would make the id read as another.
    format!(
        "{}: {} · {} at {:.1} km/h",
        printable(&t.route_id),
        t.verdict.label(),
        printable(t.type_id.as_deref().unwrap_or("unknown object")),
        f64::from(t.impact_speed) * KMH
    )
}

/// The value range of a panel: the data with a margin, always holding `must`.
fn range(values: impl Iterator<Item = f64>, must: &[f64]) -> (f64, f64) {
    let (mut lo, mut hi) = must
        .iter()
        .chain(&[])
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
            (l.min(v), h.max(v))
        });
    for v in values.filter(|v| v.is_finite()) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    let pad = ((hi - lo) * 0.08).max(0.5);
    (lo - pad, hi + pad)
}

/// Renders the figure as an SVG document.
///
/// ```
/// # use monitor_host::route::trace::{CollisionTrace, TracePoint, Verdict};
/// let points = (0..81).map(|i| TracePoint { frame: i, t: i as f64 * 0.05 - 3.0, speed: 5.0,
///     a_lon: 0.0, lat_err: None }).collect();
/// let t = CollisionTrace { route_id: "r".into(), event: 0, list: "collisions_layout",
///     type_id: None, frame: 60, time_s: 3.0, impact_speed: 5.0,
///     verdict: Verdict::Exempt, window: Some((-1.0, -0.05)), threshold: -0.5, points };
/// let svg = monitor_host::report::figure::svg(&t);
/// assert!(svg.starts_with("<svg") && svg.contains("exempt"));
/// ```
pub fn svg(t: &CollisionTrace) -> String {
    render_svg((WIDTH, HEIGHT), |root| draw(root, t))
}

/// A drawing area of the SVG backend, as every figure's `draw` takes it.
pub(crate) type Area<'a> = DrawingArea<SVGBackend<'a>, plotters::coord::Shift>;

/// What `draw` draws on a `size` canvas, as an SVG document (the one rendering of every figure:
/// the traces, the waterfall, the route chart, the forest plot).
pub(crate) fn render_svg(
    size: (u32, u32),
    draw: impl FnOnce(&Area<'_>) -> Result<(), DrawingAreaErrorKind<std::io::Error>>,
) -> String {
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, size).into_drawing_area();
        // Errors of the string backend cannot happen (it only appends to a String).
        let _ = draw(&root);
        let _ = root.present();
    }
    out
}

fn draw(
    root: &DrawingArea<SVGBackend<'_>, plotters::coord::Shift>,
    t: &CollisionTrace,
) -> Result<(), DrawingAreaErrorKind<std::io::Error>> {
    root.fill(&WHITE)?;
    let root = root.titled(&title(t), (FONT, 17).into_font().color(&BLACK))?;
    let (upper, lower) = root.split_vertically(HEIGHT / 2 - 20);
    let x = -BEFORE_S..AFTER_S;
    let speed: Vec<(f64, f64)> = t
        .points
        .iter()
        .map(|p| (p.t, f64::from(p.speed) * KMH))
        .collect();
    let acc: Vec<(f64, f64)> = t.points.iter().map(|p| (p.t, f64::from(p.a_lon))).collect();
    let thr = f64::from(t.threshold);

    let (lo, hi) = range(speed.iter().map(|p| p.1), &[0.0]);
    let mut top = ChartBuilder::on(&upper)
        .margin(8)
        .margin_right(20)
        .x_label_area_size(12)
        .y_label_area_size(56)
        .build_cartesian_2d(x.clone(), lo.max(-0.5)..hi)?;
    top.configure_mesh()
        .light_line_style(WHITE.mix(0.0))
        .bold_line_style(BLACK.mix(0.08))
        .x_labels(9)
        .x_label_formatter(&|_| String::new())
        .y_desc("speed [km/h]")
        .label_style((FONT, 12))
        .axis_desc_style((FONT, 13))
        .draw()?;
    shade_window(&mut top, t, lo.max(-0.5), hi)?;
    impact_line(&mut top, lo.max(-0.5), hi)?;
    top.draw_series(LineSeries::new(speed, SPEED.stroke_width(2)))?;
    let note = (FONT, 11).into_font();
    top.draw_series(std::iter::once(Text::new(
        "collision",
        (0.03, hi),
        note.clone().color(&IMPACT),
    )))?;
    if let Some((a, _)) = t.window {
        top.draw_series(std::iter::once(Text::new(
            "deceleration window",
            (a.max(-BEFORE_S) + 0.03, hi),
            note.color(&RGBColor(150, 110, 0)),
        )))?;
    }

    let (alo, ahi) = range(acc.iter().map(|p| p.1), &[thr - 0.5, 0.5]);
    let mut bottom = ChartBuilder::on(&lower)
        .margin(8)
        .margin_right(20)
        .x_label_area_size(40)
        .y_label_area_size(56)
        .build_cartesian_2d(x, alo..ahi)?;
    bottom
        .configure_mesh()
        .light_line_style(WHITE.mix(0.0))
        .bold_line_style(BLACK.mix(0.08))
        .x_labels(9)
        .x_label_formatter(&|v| format!("{v:.1}"))
        .y_label_formatter(&|v| format!("{v:.1}"))
        .x_desc("t − t_k [s]")
        .y_desc("a_lon [m/s²]")
        .label_style((FONT, 12))
        .axis_desc_style((FONT, 13))
        .draw()?;
    shade_window(&mut bottom, t, alo, ahi)?;
    bottom.draw_series(DashedLineSeries::new(
        [(-BEFORE_S, thr), (AFTER_S, thr)],
        6,
        4,
        THRESHOLD.stroke_width(1),
    ))?;
    impact_line(&mut bottom, alo, ahi)?;
    bottom.draw_series(LineSeries::new(acc, ACC.stroke_width(2)))?;
    bottom.draw_series(std::iter::once(Text::new(
        format!("threshold {:.1} m/s²", thr),
        (-BEFORE_S + 0.05, thr),
        (FONT, 11).into_font().color(&THRESHOLD),
    )))?;
    Ok(())
}

type Chart<'a, 'b> = ChartContext<
    'a,
    SVGBackend<'b>,
    Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
>;

/// The deceleration window, frames k - window .. k - 1, as a band (half a frame wide on each
/// side so that a one-frame window is visible).
fn shade_window(
    chart: &mut Chart<'_, '_>,
    t: &CollisionTrace,
    lo: f64,
    hi: f64,
) -> Result<(), DrawingAreaErrorKind<std::io::Error>> {
    if t.verdict == Verdict::Exempt && t.window.is_none() {
        return Ok(());
    }
    if let Some((a, b)) = t.window {
        chart.draw_series(std::iter::once(Rectangle::new(
            [(a.max(-BEFORE_S), lo), (b, hi)],
            WINDOW.mix(0.22).filled(),
        )))?;
    }
    Ok(())
}

/// The collision instant, t - t_k = 0.
fn impact_line(
    chart: &mut Chart<'_, '_>,
    lo: f64,
    hi: f64,
) -> Result<(), DrawingAreaErrorKind<std::io::Error>> {
    chart.draw_series(LineSeries::new(
        [(0.0, lo), (0.0, hi)],
        IMPACT.stroke_width(2),
    ))?;
    Ok(())
}
