//! Collision traces and their figures (docs/SCORE.md §14.4) on the demo run: the traces hold the route's
//! frames from t_k - 3 s to t_k + 1 s; the SVG holds those values (read back through the
//! figure's own axis ticks, within a pixel), the collision instant, the shaded deceleration
//! window, the threshold and the title; two runs give the same bytes (figures, CSV, HTML).

use monitor_host::report::{figure, html, trace_csv, Report};
use monitor_host::route::trace::{CollisionTrace, Verdict};
use monitor_host::{demo, route_frames, score_run, Inputs, Settings};

fn demo_report() -> (tempfile::TempDir, Inputs, Report) {
    let dir = tempfile::tempdir().unwrap();
    let run = demo::write(dir.path()).unwrap();
    let inputs = Inputs {
        telemetry: Some(run.telemetry),
        route_xml: Some(run.routes),
        ..Inputs::new([run.results])
    };
    let report = score_run(&inputs, &Settings::default()).unwrap();
    (dir, inputs, report)
}

fn traces(report: &Report) -> Vec<&CollisionTrace> {
    report.routes.iter().flat_map(|r| &r.traces).collect()
}

#[test]
fn traces_are_the_frames_around_each_aligned_collision() {
    let (_dir, inputs, report) = demo_report();
    let mut seen = Vec::new();
    for r in &report.routes {
        let aligned = r
            .collision_events
            .iter()
            .filter(|e| e.frame.is_some())
            .count();
        assert_eq!(r.traces.len(), aligned, "{:?}", r.route_id);
        for t in &r.traces {
            let e = &r.collision_events[t.event];
            assert_eq!(Some(t.frame), e.frame);
            assert_eq!(Some(t.verdict), Verdict::of(e));
            assert_eq!(Some(t.impact_speed), e.impact_speed);
            assert_eq!(Some(t.time_s), e.time_s);
            let frames = route_frames(&inputs, &t.route_id, &Settings::default())
                .unwrap()
                .frames;
            // The demo's steps are contiguous (20 Hz, one route at 10 Hz): 3 s before, 1 s after.
            let dt = r.dt.unwrap();
            let (before, after) = ((3.0 / dt).round() as usize, (1.0 / dt).round() as usize);
            let lo = t.frame.saturating_sub(before);
            let hi = (t.frame + after).min(frames.len() - 1);
            assert_eq!(t.points.len(), hi - lo + 1, "{}", t.route_id);
            for (p, j) in t.points.iter().zip(lo..=hi) {
                assert_eq!(p.frame, j);
                assert_eq!(p.speed, frames[j].speed);
                assert_eq!(p.a_lon, frames[j].a_lon);
                assert_eq!(p.lat_err, frames[j].lat_err);
                assert!((p.t - (j as f64 - t.frame as f64) * dt).abs() < 1e-12);
            }
            let (a, b) = t.window.unwrap();
            let first = t.frame.min(20) as f64;
            assert!(
                (a + first * dt).abs() < 1e-9 && (b + dt).abs() < 1e-9,
                "{a} {b}"
            );
            seen.push(t.verdict);
        }
    }
    // The demo has one collision of each verdict.
    for v in [
        Verdict::Decelerated,
        Verdict::NoDeceleration,
        Verdict::Exempt,
    ] {
        assert!(seen.contains(&v), "no {v:?} in {seen:?}");
    }
}

/// The SVG's elements this test reads: polylines by stroke colour, rectangles, texts.
struct Svg<'a>(&'a str);

fn attr<'a>(tag: &'a str, name: &str) -> Option<&'a str> {
    let key = format!(" {name}=\"");
    let i = tag.find(&key)? + key.len();
    Some(&tag[i..i + tag[i..].find('"')?])
}

impl<'a> Svg<'a> {
    fn tags(&self, name: &str) -> Vec<&'a str> {
        let open = format!("<{name} ");
        self.0
            .match_indices(&open)
            .map(|(i, _)| &self.0[i..i + self.0[i..].find('>').unwrap()])
            .collect()
    }
    /// Points of the polylines drawn in `stroke`.
    fn lines(&self, stroke: &str) -> Vec<Vec<(f64, f64)>> {
        self.tags("polyline")
            .into_iter()
            .filter(|t| attr(t, "stroke") == Some(stroke))
            .map(|t| {
                attr(t, "points")
                    .unwrap()
                    .split_whitespace()
                    .map(|p| {
                        let (x, y) = p.split_once(',').unwrap();
                        (x.parse().unwrap(), y.parse().unwrap())
                    })
                    .collect()
            })
            .collect()
    }
    /// `(x, y, text)` of every `<text>`.
    fn texts(&self) -> Vec<(f64, f64, String)> {
        self.0
            .match_indices("<text ")
            .map(|(i, _)| {
                let tag = &self.0[i..i + self.0[i..].find('>').unwrap()];
                let body = &self.0[i + tag.len() + 1..];
                let body = body[..body.find("</text>").unwrap()].trim().to_string();
                let n = |a| attr(tag, a).unwrap().parse().unwrap();
                (n("x"), n("y"), body)
            })
            .collect()
    }
}

/// A linear map fitted through an axis' tick labels `(pixel, value)`.
#[derive(Debug)]
struct Axis {
    a: f64,
    b: f64,
    per_px: f64,
}

impl Axis {
    fn fit(ticks: &[(f64, f64)]) -> Axis {
        assert!(ticks.len() >= 3, "ticks {ticks:?}");
        let (p0, v0) = ticks[0];
        let (p1, v1) = ticks[ticks.len() - 1];
        let b = (v1 - v0) / (p1 - p0);
        let axis = Axis {
            a: v0 - b * p0,
            b,
            per_px: b.abs(),
        };
        // Every tick agrees with the fit within a pixel (pixels are integers).
        for &(p, v) in ticks {
            assert!((axis.value(p) - v).abs() <= 1.01 * axis.per_px, "{ticks:?}");
        }
        axis
    }
    fn value(&self, px: f64) -> f64 {
        self.a + self.b * px
    }
}

fn check_figure(t: &CollisionTrace) {
    let svg_text = figure::svg(t);
    let svg = Svg(&svg_text);
    let texts = svg.texts();
    assert!(
        texts.iter().any(|(_, _, s)| *s == figure::title(t)),
        "title of {}",
        t.route_id
    );
    let title = figure::title(t);
    assert!(title.contains(&t.route_id) && title.contains(t.verdict.label()));
    assert!(title.contains(&format!("{:.1} km/h", f64::from(t.impact_speed) * 3.6)));
    if let Some(ty) = &t.type_id {
        assert!(title.contains(ty.as_str()));
    }
    let split = f64::from(figure::HEIGHT) / 2.0;
    let num = |s: &str| s.parse::<f64>().ok();
    // y tick labels: right-aligned at x 54, the upper panel above the split.
    let yticks = |upper: bool| -> Vec<(f64, f64)> {
        let mut v: Vec<(f64, f64)> = texts
            .iter()
            .filter(|(x, y, _)| *x == 54.0 && (*y < split) == upper)
            .filter_map(|(_, y, s)| Some((*y, num(s)?)))
            .collect();
        v.sort_by(|a, b| a.0.total_cmp(&b.0));
        v
    };
    let xticks: Vec<(f64, f64)> = texts
        .iter()
        .filter(|(x, y, _)| {
            *x != 54.0 && *y > split + 150.0 && *y < f64::from(figure::HEIGHT) - 20.0
        })
        .filter_map(|(x, _, s)| Some((*x, num(s)?)))
        .collect();
    let (tx, sy, ay) = (
        Axis::fit(&xticks),
        Axis::fit(&yticks(true)),
        Axis::fit(&yticks(false)),
    );

    let check_series = |stroke: &str, y: &Axis, value: &dyn Fn(usize) -> f64| {
        let lines = svg.lines(stroke);
        assert_eq!(lines.len(), 1, "one {stroke} series in {}", t.route_id);
        let pts = &lines[0];
        assert_eq!(pts.len(), t.points.len());
        for (i, (&(px, py), p)) in pts.iter().zip(&t.points).enumerate() {
            assert!((tx.value(px) - p.t).abs() <= 1.01 * tx.per_px, "t {i}");
            assert!(
                (y.value(py) - value(i)).abs() <= 1.01 * y.per_px,
                "{stroke} point {i}: drawn {} for {}",
                y.value(py),
                value(i)
            );
        }
    };
    check_series("#1F77B4", &sy, &|i| f64::from(t.points[i].speed) * 3.6);
    check_series("#2C2C2C", &ay, &|i| f64::from(t.points[i].a_lon));

    // The collision instant: a vertical red line at t = 0 in each panel.
    let impact = svg.lines("#D62728");
    assert_eq!(impact.len(), 2);
    for l in &impact {
        assert_eq!(l[0].0, l[1].0);
        assert!(tx.value(l[0].0).abs() <= 1.01 * tx.per_px);
    }
    // The threshold: dashes at a_lon = threshold across the panel.
    let dashes = svg.lines("#787878");
    assert!(dashes.len() > 10, "dashed threshold");
    for d in &dashes {
        for &(_, y) in d {
            assert!((ay.value(y) - f64::from(t.threshold)).abs() <= 1.01 * ay.per_px);
        }
    }
    // The deceleration window, shaded in both panels.
    let shades: Vec<&str> = svg
        .tags("rect")
        .into_iter()
        .filter(|r| attr(r, "fill") == Some("#FFBF00"))
        .collect();
    let (a, b) = t.window.unwrap();
    assert_eq!(shades.len(), 2);
    for r in shades {
        let x: f64 = attr(r, "x").unwrap().parse().unwrap();
        let w: f64 = attr(r, "width").unwrap().parse().unwrap();
        assert!((tx.value(x) - a).abs() <= 1.01 * tx.per_px);
        assert!((tx.value(x + w) - b).abs() <= 1.51 * tx.per_px);
    }
}

#[test]
fn figures_hold_the_series_the_marks_and_the_title() {
    let (_dir, _inputs, report) = demo_report();
    let all = traces(&report);
    let aligned = report
        .routes
        .iter()
        .flat_map(|r| &r.collision_events)
        .filter(|e| e.frame.is_some())
        .count();
    assert!(aligned >= 4);
    assert_eq!(all.len(), aligned);
    for t in all {
        check_figure(t);
    }
}

#[test]
fn two_runs_give_identical_bytes() {
    let (d1, _i1, a) = demo_report();
    let (d2, _i2, b) = demo_report();
    let (ta, tb) = (traces(&a), traces(&b));
    assert_eq!(ta.len(), tb.len());
    for (x, y) in ta.iter().zip(&tb) {
        assert_eq!(figure::svg(x), figure::svg(y));
        assert_eq!(trace_csv::csv(x), trace_csv::csv(y));
    }
    let opts = Default::default();
    // The pages name their source files by folder and name: the two runs' folders differ,
    // nothing else may.
    let page = |r: &Report, d: &tempfile::TempDir| {
        let folder = d.path().file_name().unwrap().to_string_lossy().into_owned();
        html::page(r, &opts, "demo")
            .replace(&d.path().display().to_string(), "DIR")
            .replace(&folder, "DIR")
    };
    assert!(page(&a, &d1) == page(&b, &d2), "the HTML pages differ");
}

#[test]
fn trace_csv_has_a_line_per_frame() {
    let (_dir, _inputs, report) = demo_report();
    for r in &report.routes {
        for t in &r.traces {
            let dt = r.dt.unwrap();
            let csv = trace_csv::csv(t);
            let lines: Vec<&str> = csv.lines().collect();
            assert_eq!(lines[0], trace_csv::HEADER);
            assert_eq!(lines.len(), t.points.len() + 1);
            let zero = lines
                .iter()
                .find(|l| l.split(',').nth(1) == Some("0"))
                .unwrap();
            assert_eq!(zero.split(',').next().unwrap(), t.frame.to_string());
            let first = (-3.0f64).max(-dt * t.frame as f64);
            let t0: f64 = lines[1].split(',').nth(1).unwrap().parse().unwrap();
            assert!((t0 - first).abs() < 1e-9, "{t0} {first}");
        }
    }
}
