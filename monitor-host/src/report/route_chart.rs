//! DS and DS_safe of every route, one column each, sorted (DS descending, then DS_safe
//! descending, then input order): a grey bar for DS and, inside it, a bar for DS_safe coloured by
//! the route's state. The gap between the two is the route's loss to the SDS factors (its
//! `decomposition`). Drawn like the collision figure ([`crate::report::figure`]).

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::pipeline::outcome::RouteState;
use crate::report::RouteReport;

/// Figure width, px.
pub const WIDTH: u32 = 720;
/// Figure height, px.
pub const HEIGHT: u32 = 320;

const DS: RGBColor = RGBColor(200, 200, 200);
const FONT: &str = "sans-serif";

/// The colour of a state (the legend's order: scored, missing, invalid, foreign).
pub fn colour(state: &RouteState) -> RGBColor {
    match state {
        RouteState::Scored => RGBColor(31, 119, 180),
        RouteState::Missing => RGBColor(255, 127, 14),
        RouteState::Invalid(_) => RGBColor(214, 39, 40),
        RouteState::Foreign => RGBColor(148, 103, 189),
    }
}

/// The routes' indices in the chart's order: DS descending (a route without one as 0), then
/// DS_safe descending (none last), then input order.
///
/// ```
/// let order = monitor_host::report::route_chart::order(&[]);
/// assert!(order.is_empty());
/// ```
pub fn order(routes: &[RouteReport]) -> Vec<usize> {
    let mut idx: Vec<usize> = (0..routes.len()).collect();
    let key = |r: &RouteReport| {
        (
            r.score_composed.unwrap_or(0.0),
            r.ds_safe.unwrap_or(f64::NEG_INFINITY),
        )
    };
    idx.sort_by(|&a, &b| {
        let (ka, kb) = (key(&routes[a]), key(&routes[b]));
        kb.0.total_cmp(&ka.0)
            .then(kb.1.total_cmp(&ka.1))
            .then(a.cmp(&b))
    });
    idx
}

/// Renders the chart as an SVG document.
///
/// ```
/// let svg = monitor_host::report::route_chart::svg(&[]);
/// assert!(svg.starts_with("<svg") && svg.contains("DS_safe"));
/// ```
pub fn svg(routes: &[RouteReport]) -> String {
    crate::report::figure::render_svg((WIDTH, HEIGHT), |root| draw(root, routes))
}

fn draw(
    root: &DrawingArea<SVGBackend<'_>, plotters::coord::Shift>,
    routes: &[RouteReport],
) -> Result<(), DrawingAreaErrorKind<std::io::Error>> {
    root.fill(&WHITE)?;
    let area = root.titled(
        &format!("DS and DS_safe per route ({} routes, sorted)", routes.len()),
        (FONT, 17).into_font().color(&BLACK),
    )?;
    let n = routes.len().max(1) as f64;
    let mut chart = ChartBuilder::on(&area)
        .margin(8)
        .margin_top(24)
        .margin_right(20)
        .x_label_area_size(30)
        .y_label_area_size(48)
        .build_cartesian_2d(0.0..n, 0.0..105.0)?;
    chart
        .configure_mesh()
        .light_line_style(WHITE.mix(0.0))
        .bold_line_style(BLACK.mix(0.08))
        .disable_x_mesh()
        .x_labels(0)
        .x_label_formatter(&|_| String::new())
        .x_desc("routes, by DS")
        .y_desc("score")
        .label_style((FONT, 12))
        .axis_desc_style((FONT, 13))
        .draw()?;
    for (x, &i) in order(routes).iter().enumerate() {
        let r = &routes[i];
        let x = x as f64;
        let ds = r.score_composed.unwrap_or(0.0);
        chart.draw_series(std::iter::once(Rectangle::new(
            [(x + 0.05, 0.0), (x + 0.95, ds)],
            DS.filled(),
        )))?;
        if let Some(safe) = r.ds_safe {
            chart.draw_series(std::iter::once(Rectangle::new(
                [(x + 0.2, 0.0), (x + 0.8, safe)],
                colour(&r.state).filled(),
            )))?;
        }
    }
    // The legend, in pixels above the plot.
    let font = (FONT, 12)
        .into_font()
        .color(&BLACK)
        .pos(Pos::new(HPos::Left, VPos::Center));
    let items = [
        ("DS", DS),
        ("DS_safe, scored", colour(&RouteState::Scored)),
        ("missing", colour(&RouteState::Missing)),
        (
            "invalid (no DS_safe)",
            colour(&RouteState::Invalid(String::new())),
        ),
        ("foreign", colour(&RouteState::Foreign)),
    ];
    let mut px = 70;
    let py = 40;
    for (name, c) in items {
        root.draw(&Rectangle::new(
            [(px, py - 5), (px + 10, py + 5)],
            c.filled(),
        ))?;
        root.draw(&Text::new(name, (px + 14, py), font.clone()))?;
        px += 22 + 6 * name.len() as i32;
    }
    Ok(())
}
