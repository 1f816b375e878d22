//! Route reference (`SDS-SPEC.md` §1.3) and per-frame lateral error (§2).
//!
//! A Bench2Drive route XML (`<routes><route id town><waypoints><position x y z/>...`) is read with
//! a streaming XML reader into a [`RouteSet`]. The reference polyline of a route is the straight
//! segments between consecutive waypoints (CARLA x, y). A [`LateralTracker`] follows one replayed
//! drive along that polyline with the spec's bounded forward search and yields `lat_err` per frame.
//!
//! ```
//! use monitor_host::route::{parse, LateralTracker};
//!
//! let set = parse(r#"<routes><route id="7" town="Town01"><waypoints>
//!     <position x="0" y="0" z="0"/><position x="2" y="0" z="0"/>
//!     <position x="30" y="0" z="0"/><position x="32" y="0" z="0"/>
//!   </waypoints></route></routes>"#)?;
//! let route = set.get("7").expect("route 7");
//! assert_eq!(route.town, "Town01");
//! let mut tracker = LateralTracker::new(route, 8.0, 10.0);
//! assert_eq!(tracker.next([1.0, 0.5]), Some(0.5));   // beside segment 0
//! assert_eq!(tracker.next([15.0, 1.0]), None);       // beside the 28 m junction gap
//! assert_eq!(tracker.next([31.0, -0.25]), Some(0.25));
//! # Ok::<(), monitor_host::route::RouteError>(())
//! ```

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use quick_xml::events::{BytesStart, Event};
use quick_xml::Reader;

/// One route of the XML: its id, town and waypoints (CARLA world x, y in metres; z dropped).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RouteRef {
    /// The XML `id` attribute (the `<xmlid>` of `RouteScenario_<xmlid>_rep<k>`).
    pub id: String,
    /// The XML `town` attribute (empty if absent).
    pub town: String,
    /// The waypoints in document order.
    pub waypoints: Vec<[f64; 2]>,
}

/// Why a route file or one of its routes cannot be used. Names the file and the route id.
#[derive(Debug, thiserror::Error)]
pub enum RouteError {
    /// The file cannot be read.
    #[error("cannot read route file {}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The OS error.
        #[source]
        source: std::io::Error,
    },
    /// The XML is not well formed (the whole set is rejected).
    #[error("{file}: malformed XML at line {line} (byte {offset}): {message}")]
    Xml {
        /// The file (`<memory>` for [`parse`]).
        file: String,
        /// 1-based line of the error.
        line: usize,
        /// Byte offset of the error.
        offset: u64,
        /// The parser's message.
        message: String,
    },
    /// A `<route>` without an `id` attribute (the whole set is rejected: it cannot be named).
    #[error("{file}: route #{index} (1-based) has no id attribute")]
    MissingId {
        /// The file.
        file: String,
        /// 1-based position of the route in the file.
        index: usize,
    },
    /// A route without any waypoint.
    #[error("{file}: route {route}: no waypoints")]
    NoWaypoints {
        /// The file.
        file: String,
        /// The route id.
        route: String,
    },
    /// A waypoint whose `x` or `y` is missing or not a finite number.
    #[error("{file}: route {route}: waypoint {index}: {problem}")]
    BadWaypoint {
        /// The file.
        file: String,
        /// The route id.
        route: String,
        /// 0-based waypoint index.
        index: usize,
        /// What is wrong (e.g. `attribute y missing`, `x = "abc" is not a finite number`).
        problem: String,
    },
    /// Two routes with the same id (the first is kept).
    #[error("{file}: route {route}: id appears twice (the first is used)")]
    DuplicateId {
        /// The file.
        file: String,
        /// The route id.
        route: String,
    },
    /// No route with that id.
    #[error("{file}: route {route}: not found")]
    NotFound {
        /// The file.
        file: String,
        /// The route id looked up.
        route: String,
    },
}

impl Clone for RouteError {
    fn clone(&self) -> Self {
        match self {
            RouteError::Io { path, source } => RouteError::Io {
                path: path.clone(),
                source: std::io::Error::new(source.kind(), source.to_string()),
            },
            RouteError::Xml {
                file,
                line,
                offset,
                message,
            } => RouteError::Xml {
                file: file.clone(),
                line: *line,
                offset: *offset,
                message: message.clone(),
            },
            RouteError::MissingId { file, index } => RouteError::MissingId {
                file: file.clone(),
                index: *index,
            },
            RouteError::NoWaypoints { file, route } => RouteError::NoWaypoints {
                file: file.clone(),
                route: route.clone(),
            },
            RouteError::BadWaypoint {
                file,
                route,
                index,
                problem,
            } => RouteError::BadWaypoint {
                file: file.clone(),
                route: route.clone(),
                index: *index,
                problem: problem.clone(),
            },
            RouteError::DuplicateId { file, route } => RouteError::DuplicateId {
                file: file.clone(),
                route: route.clone(),
            },
            RouteError::NotFound { file, route } => RouteError::NotFound {
                file: file.clone(),
                route: route.clone(),
            },
        }
    }
}

/// The routes of one XML file, by id.
///
/// Routes that cannot be used (no waypoints, a bad coordinate) do not stop the set from loading:
/// [`RouteSet::get`] skips them and [`RouteSet::get_checked`] says why. A duplicate id keeps the
/// first route and is listed in [`RouteSet::problems`].
#[derive(Debug, Clone, Default)]
pub struct RouteSet {
    file: String,
    routes: Vec<RouteRef>,
    /// Per route (same index): why it is unusable.
    broken: Vec<Option<RouteError>>,
    index: HashMap<String, usize>,
    problems: Vec<RouteError>,
}

impl RouteSet {
    /// The usable route with this XML id (at least one waypoint, all coordinates valid).
    pub fn get(&self, xml_id: &str) -> Option<&RouteRef> {
        self.get_checked(xml_id).ok()
    }

    /// The route with this XML id, or why it cannot be used (naming file and route).
    ///
    /// # Errors
    /// [`RouteError::NotFound`], [`RouteError::NoWaypoints`] or [`RouteError::BadWaypoint`].
    pub fn get_checked(&self, xml_id: &str) -> Result<&RouteRef, RouteError> {
        let Some(&i) = self.index.get(xml_id) else {
            return Err(RouteError::NotFound {
                file: self.file.clone(),
                route: xml_id.to_string(),
            });
        };
        match &self.broken[i] {
            Some(e) => Err(e.clone()),
            None => Ok(&self.routes[i]),
        }
    }

    /// Number of routes in the file (usable or not, duplicates counted once per element).
    pub fn len(&self) -> usize {
        self.routes.len()
    }

    /// True when the file has no route.
    pub fn is_empty(&self) -> bool {
        self.routes.is_empty()
    }

    /// Every route in document order, usable or not.
    pub fn iter(&self) -> impl Iterator<Item = &RouteRef> {
        self.routes.iter()
    }

    /// Every problem found while loading: unusable routes and duplicate ids, in document order.
    pub fn problems(&self) -> &[RouteError] {
        &self.problems
    }

    /// The file name used in error messages (`<memory>` for [`parse`]).
    pub fn file(&self) -> &str {
        &self.file
    }
}

/// Loads a route XML file (see [`parse`]).
///
/// # Errors
/// [`RouteError::Io`] if unreadable, otherwise as [`parse`] (naming this file).
pub fn load(path: &Path) -> Result<RouteSet, RouteError> {
    let bytes = std::fs::read(path).map_err(|source| RouteError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let file = path.display().to_string();
    let text = match std::str::from_utf8(&bytes) {
        Ok(t) => t,
        Err(e) => {
            let offset = e.valid_up_to();
            return Err(RouteError::Xml {
                line: line_of(&bytes, offset),
                offset: offset as u64,
                message: "not valid UTF-8".into(),
                file,
            });
        }
    };
    parse_named(text, &file)
}

/// Parses route XML held in memory (errors name the file `<memory>`).
///
/// Reads every `<route id town>` element and the `<position x y>` elements directly inside its
/// `<waypoints>`; everything else (scenarios, trigger points, weathers) is skipped.
///
/// # Errors
/// [`RouteError::Xml`] for malformed XML (with line and byte offset), [`RouteError::MissingId`]
/// for a route without id. Per-route problems do not fail the set (see [`RouteSet`]).
pub fn parse(xml: &str) -> Result<RouteSet, RouteError> {
    parse_named(xml, "<memory>")
}

fn line_of(bytes: &[u8], offset: usize) -> usize {
    1 + bytes[..offset.min(bytes.len())]
        .iter()
        .filter(|&&b| b == b'\n')
        .count()
}

/// The route element being read.
struct Open {
    route: RouteRef,
    error: Option<RouteError>,
    depth: usize,
    waypoints_depth: Option<usize>,
}

impl Open {
    /// Records waypoint `index` as bad; the first problem of a route is the one reported.
    fn bad_waypoint(&mut self, file: &str, index: usize, problem: String) {
        if self.error.is_none() {
            self.error = Some(RouteError::BadWaypoint {
                file: file.to_string(),
                route: self.route.id.clone(),
                index,
                problem,
            });
        }
    }
}

fn parse_named(xml: &str, file: &str) -> Result<RouteSet, RouteError> {
    let mut reader = Reader::from_str(xml);
    reader.config_mut().check_end_names = true;
    let mut set = RouteSet {
        file: file.to_string(),
        ..RouteSet::default()
    };
    let xml_err = |reader: &Reader<&[u8]>, message: String| {
        let offset = reader.error_position();
        RouteError::Xml {
            file: file.to_string(),
            line: line_of(xml.as_bytes(), offset as usize),
            offset,
            message,
        }
    };
    let mut depth = 0usize;
    let mut open: Option<Open> = None;
    let mut route_count = 0usize;
    loop {
        let event = match reader.read_event() {
            Ok(e) => e,
            Err(e) => return Err(xml_err(&reader, e.to_string())),
        };
        match event {
            Event::Start(e) => {
                depth += 1;
                handle_element(&reader, &e, depth, &mut open, &mut route_count, file, false)?;
            }
            Event::Empty(e) => {
                handle_element(
                    &reader,
                    &e,
                    depth + 1,
                    &mut open,
                    &mut route_count,
                    file,
                    true,
                )?;
                if let Some(done) = close_route(&mut open, depth + 1) {
                    finish_route(&mut set, done);
                }
            }
            Event::End(_) => {
                if let Some(o) = open.as_mut() {
                    if o.waypoints_depth == Some(depth) {
                        o.waypoints_depth = None;
                    }
                }
                if let Some(done) = close_route(&mut open, depth) {
                    finish_route(&mut set, done);
                }
                depth = depth.saturating_sub(1);
            }
            Event::Eof => {
                if depth != 0 || open.is_some() {
                    return Err(xml_err(&reader, "unexpected end of file".into()));
                }
                return Ok(set);
            }
            _ => {}
        }
    }
}

/// Takes the open route if the element closing at `depth` is the route itself.
fn close_route(open: &mut Option<Open>, depth: usize) -> Option<Open> {
    if open.as_ref().is_some_and(|o| o.depth == depth) {
        open.take()
    } else {
        None
    }
}

fn finish_route(set: &mut RouteSet, mut done: Open) {
    let id = done.route.id.clone();
    if done.error.is_none() && done.route.waypoints.is_empty() {
        done.error = Some(RouteError::NoWaypoints {
            file: set.file.clone(),
            route: id.clone(),
        });
    }
    if let Some(e) = &done.error {
        set.problems.push(e.clone());
    }
    if set.index.contains_key(&id) {
        set.problems.push(RouteError::DuplicateId {
            file: set.file.clone(),
            route: id,
        });
    } else {
        set.index.insert(id, set.routes.len());
    }
    set.routes.push(done.route);
    set.broken.push(done.error);
}

fn attr_string(
    reader: &Reader<&[u8]>,
    e: &BytesStart<'_>,
    name: &[u8],
) -> Result<Option<String>, String> {
    for a in e.attributes() {
        let a = a.map_err(|err| err.to_string())?;
        if a.key.as_ref() == name {
            return a
                .decode_and_unescape_value(reader.decoder())
                .map(|v| Some(v.into_owned()))
                .map_err(|err| err.to_string());
        }
    }
    Ok(None)
}

fn handle_element(
    reader: &Reader<&[u8]>,
    e: &BytesStart<'_>,
    depth: usize,
    open: &mut Option<Open>,
    route_count: &mut usize,
    file: &str,
    empty: bool,
) -> Result<(), RouteError> {
    let name = e.name();
    match name.as_ref() {
        b"route" => {
            if open.is_some() {
                return Err(xml_error_at(reader, file, "nested <route> element".into()));
            }
            *route_count += 1;
            let id = attr_string(reader, e, b"id")
                .map_err(|m| xml_error_at(reader, file, m))?
                .ok_or_else(|| RouteError::MissingId {
                    file: file.to_string(),
                    index: *route_count,
                })?;
            let town = attr_string(reader, e, b"town")
                .map_err(|m| xml_error_at(reader, file, m))?
                .unwrap_or_default();
            *open = Some(Open {
                route: RouteRef {
                    id,
                    town,
                    waypoints: Vec::new(),
                },
                error: None,
                depth,
                waypoints_depth: None,
            });
        }
        b"waypoints" => {
            if let Some(o) = open.as_mut() {
                if o.depth + 1 == depth && !empty {
                    o.waypoints_depth = Some(depth);
                }
            }
        }
        b"position" => {
            if let Some(o) = open.as_mut() {
                if o.waypoints_depth.is_some_and(|w| w + 1 == depth) {
                    read_position(reader, e, o, file)?;
                }
            }
        }
        _ => {}
    }
    Ok(())
}

fn xml_error_at(reader: &Reader<&[u8]>, file: &str, message: String) -> RouteError {
    let offset = reader.buffer_position();
    RouteError::Xml {
        file: file.to_string(),
        line: line_of(reader.get_ref(), offset as usize),
        offset,
        message,
    }
}

fn read_position(
    reader: &Reader<&[u8]>,
    e: &BytesStart<'_>,
    o: &mut Open,
    file: &str,
) -> Result<(), RouteError> {
    let index = o.route.waypoints.len();
    let mut xy: [Option<f64>; 2] = [None, None];
    for a in e.attributes() {
        let a = a.map_err(|err| xml_error_at(reader, file, err.to_string()))?;
        let slot = match a.key.as_ref() {
            b"x" => 0,
            b"y" => 1,
            _ => continue,
        };
        let text = std::str::from_utf8(&a.value).unwrap_or("");
        match text.trim().parse::<f64>() {
            Ok(v) if v.is_finite() => xy[slot] = Some(v),
            _ => {
                let problem = format!(
                    "{} = {:?} is not a finite number",
                    if slot == 0 { "x" } else { "y" },
                    text.chars().take(40).collect::<String>()
                );
                o.bad_waypoint(file, index, problem);
                return Ok(());
            }
        }
    }
    match xy {
        [Some(x), Some(y)] => o.route.waypoints.push([x, y]),
        _ => {
            let missing = if xy[0].is_none() { "x" } else { "y" };
            o.bad_waypoint(file, index, format!("attribute {missing} missing"));
        }
    }
    Ok(())
}

/// Follows a drive along a route's reference polyline and yields the lateral error per frame
/// (`SDS-SPEC.md` §2).
///
/// Bounded forward search: the matched segment index `m` starts at 0; for each frame the
/// candidates are the segments `j >= m` whose start lies at most `lookahead` metres of route length
/// beyond the end of segment `m`. The nearest candidate (distance to the clamped segment) wins,
/// a later segment only if strictly nearer; `m` moves to it, also onto a junction gap (a segment
/// strictly longer than `gap_max`), where the lateral error is unknown.
///
/// Distances are computed in f64 relative to the segment start. The route's cumulative length is
/// computed once, in [`LateralTracker::new`]; each frame costs O(candidates).
#[derive(Debug, Clone)]
pub struct LateralTracker<'a> {
    waypoints: &'a [[f64; 2]],
    /// `cum[i]` = route length from waypoint 0 to waypoint i (summed in order).
    cum: Vec<f64>,
    m: usize,
    gap_max: f64,
    lookahead: f64,
}

impl<'a> LateralTracker<'a> {
    /// A tracker at the start of `route` (spec defaults: `gap_max = 8.0`, `lookahead = 10.0`).
    pub fn new(route: &'a RouteRef, gap_max: f64, lookahead: f64) -> Self {
        let waypoints = &route.waypoints[..];
        let mut cum = Vec::with_capacity(waypoints.len());
        let mut total = 0.0f64;
        for (i, w) in waypoints.iter().enumerate() {
            if i > 0 {
                total += seg_len(waypoints[i - 1], *w);
            }
            cum.push(total);
        }
        LateralTracker {
            waypoints,
            cum,
            m: 0,
            gap_max,
            lookahead,
        }
    }

    /// The lateral error of a frame at `loc` (2-D), or `None` when unknown: the matched segment is
    /// a junction gap, or the route has fewer than 2 waypoints (no segment).
    pub fn next(&mut self, loc: [f64; 2]) -> Option<f64> {
        let nseg = self.waypoints.len().checked_sub(1)?;
        if nseg == 0 {
            return None;
        }
        let m = self.m;
        let limit = self.cum[m + 1] + self.lookahead;
        let mut best = m;
        let mut best_d = self.dist_to_segment(m, loc);
        let mut j = m + 1;
        while j < nseg && self.cum[j] <= limit {
            let d = self.dist_to_segment(j, loc);
            if d < best_d {
                best = j;
                best_d = d;
            }
            j += 1;
        }
        self.m = best;
        if seg_len(self.waypoints[best], self.waypoints[best + 1]) > self.gap_max {
            None
        } else {
            Some(best_d)
        }
    }

    /// The currently matched segment index `m` (segment `m` joins waypoints `m` and `m + 1`).
    pub fn segment(&self) -> usize {
        self.m
    }

    /// Route length from the first waypoint to waypoint `i` (None if out of range).
    pub fn length_to(&self, i: usize) -> Option<f64> {
        self.cum.get(i).copied()
    }

    /// Distance from `p` to the clamped segment `j`, relative to the segment start.
    fn dist_to_segment(&self, j: usize, p: [f64; 2]) -> f64 {
        let a = self.waypoints[j];
        let b = self.waypoints[j + 1];
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let (px, py) = (p[0] - a[0], p[1] - a[1]);
        let len2 = dx * dx + dy * dy;
        let t = if len2 > 0.0 {
            ((px * dx + py * dy) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let (ex, ey) = (px - t * dx, py - t * dy);
        (ex * ex + ey * ey).sqrt()
    }
}

fn seg_len(a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    (dx * dx + dy * dy).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn route(points: &[[f64; 2]]) -> RouteRef {
        RouteRef {
            id: "r".into(),
            town: "Town01".into(),
            waypoints: points.to_vec(),
        }
    }

    fn close(a: Option<f64>, b: f64) -> bool {
        a.is_some_and(|a| (a - b).abs() < 1e-12)
    }

    #[test]
    fn parses_routes_and_skips_other_positions() {
        let set = parse(
            r#"<?xml version="1.0"?>
<routes>
  <route id="1" town="Town12">
    <waypoints>
      <position x="-497.6" y="3672.9" z="364.9" />
      <position x="-497.6" y="3670.9" z="364.8"></position>
    </waypoints>
    <scenarios><scenario name="A_1" type="A">
      <trigger_point x="1" y="2" yaw="0" z="0"/>
      <position x="999" y="999" z="0"/>
    </scenario></scenarios>
    <weathers><weather route_percentage="0"/></weathers>
  </route>
  <route id="2" town="Town&amp;X"><waypoints><position x="5" y="6" z="0"/></waypoints></route>
</routes>"#,
        )
        .unwrap();
        assert_eq!(set.len(), 2);
        let r1 = set.get("1").unwrap();
        assert_eq!(r1.town, "Town12");
        assert_eq!(r1.waypoints, vec![[-497.6, 3672.9], [-497.6, 3670.9]]);
        assert_eq!(set.get("2").unwrap().town, "Town&X");
        assert_eq!(set.get("2").unwrap().waypoints, vec![[5.0, 6.0]]);
        assert!(set.get("3").is_none());
        assert!(set.problems().is_empty());
        assert_eq!(
            set.get_checked("3").unwrap_err().to_string(),
            "<memory>: route 3: not found"
        );
    }

    #[test]
    fn route_without_waypoints_keeps_the_set() {
        let set = parse(
            r#"<routes><route id="9" town="T"><waypoints></waypoints></route>
               <route id="10" town="T"/>
               <route id="11" town="T"><waypoints><position x="0" y="0"/></waypoints></route></routes>"#,
        )
        .unwrap();
        assert_eq!(set.len(), 3);
        assert!(set.get("9").is_none());
        assert_eq!(
            set.get_checked("9").unwrap_err().to_string(),
            "<memory>: route 9: no waypoints"
        );
        assert_eq!(
            set.get_checked("10").unwrap_err().to_string(),
            "<memory>: route 10: no waypoints"
        );
        assert!(set.get("11").is_some());
        assert_eq!(set.problems().len(), 2);
    }

    #[test]
    fn bad_waypoints_and_duplicates() {
        let set = parse(
            r#"<routes><route id="1" town="T"><waypoints><position x="0" y="0"/><position x="abc" y="0"/></waypoints></route>
               <route id="2" town="T"><waypoints><position x="0"/></waypoints></route>
               <route id="3" town="A"><waypoints><position x="0" y="0"/></waypoints></route>
               <route id="3" town="B"><waypoints><position x="0" y="0"/></waypoints></route></routes>"#,
        )
        .unwrap();
        assert_eq!(
            set.get_checked("1").unwrap_err().to_string(),
            r#"<memory>: route 1: waypoint 1: x = "abc" is not a finite number"#
        );
        assert_eq!(
            set.get_checked("2").unwrap_err().to_string(),
            "<memory>: route 2: waypoint 0: attribute y missing"
        );
        assert_eq!(set.get("3").unwrap().town, "A");
        assert_eq!(
            set.problems().last().unwrap().to_string(),
            "<memory>: route 3: id appears twice (the first is used)"
        );
    }

    #[test]
    fn malformed_xml_names_position() {
        let e = parse("<routes>\n<route id=\"1\" town=\"T\">\n<waypoints>\n</route></routes>")
            .unwrap_err();
        let s = e.to_string();
        assert!(s.starts_with("<memory>: malformed XML at line 4 "), "{s}");
        let e = parse("<routes><route id=\"1\">").unwrap_err().to_string();
        assert!(e.contains("malformed XML"), "{e}");
        let e = parse("<routes><route town=\"T\"/></routes>").unwrap_err();
        assert_eq!(
            e.to_string(),
            "<memory>: route #1 (1-based) has no id attribute"
        );
        let e = load(Path::new("/nonexistent/routes.xml")).unwrap_err();
        assert!(e
            .to_string()
            .starts_with("cannot read route file /nonexistent/routes.xml: "));
    }

    #[test]
    fn load_names_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("r.xml");
        std::fs::write(&p, "<routes><route id=\"4\" town=\"T\"></route></routes>").unwrap();
        let set = load(&p).unwrap();
        let s = set.get_checked("4").unwrap_err().to_string();
        assert_eq!(s, format!("{}: route 4: no waypoints", p.display()));
    }

    #[test]
    fn straight_route() {
        let r = route(&[[0.0, 0.0], [2.0, 0.0], [4.0, 0.0], [6.0, 0.0]]);
        let mut t = LateralTracker::new(&r, 8.0, 10.0);
        assert!(close(t.next([0.5, 0.3]), 0.3));
        assert!(close(t.next([3.0, -1.25]), 1.25));
        assert_eq!(t.segment(), 1);
        assert!(close(t.next([5.0, 0.0]), 0.0));
        assert_eq!(t.segment(), 2);
        assert_eq!(t.length_to(3), Some(6.0));
    }

    #[test]
    fn beyond_the_end_uses_clamped_distance() {
        let r = route(&[[0.0, 0.0], [2.0, 0.0], [4.0, 0.0]]);
        let mut t = LateralTracker::new(&r, 8.0, 10.0);
        // (7, 4) is 3 m past the end and 4 m to the side: distance to the end point is 5.
        assert!(close(t.next([7.0, 4.0]), 5.0));
        assert_eq!(t.segment(), 1);
        // Before the start: distance to waypoint 0, but the tracker never goes back.
        let mut t = LateralTracker::new(&r, 8.0, 10.0);
        assert!(close(t.next([-3.0, 4.0]), 5.0));
        assert_eq!(t.segment(), 0);
    }

    #[test]
    fn gap_segment_is_unknown_and_m_moves_onto_it() {
        // Segment 1 is 20 m long (> 8): a junction gap. Segment 2 is 2 m.
        let r = route(&[[0.0, 0.0], [2.0, 0.0], [22.0, 0.0], [24.0, 0.0]]);
        let mut t = LateralTracker::new(&r, 8.0, 10.0);
        assert!(close(t.next([1.0, 0.5]), 0.5));
        assert_eq!(t.next([10.0, 0.5]), None);
        assert_eq!(t.segment(), 1, "m moves onto the gap");
        // From the gap, segment 2 (start 22 m <= end of gap 22 m + 10) is a candidate.
        assert!(close(t.next([23.0, 0.25]), 0.25));
        assert_eq!(t.segment(), 2);
    }

    #[test]
    fn gap_boundary_is_strict() {
        // Exactly 8 m is not a gap; 8.5 m is.
        let r = route(&[[0.0, 0.0], [8.0, 0.0], [16.5, 0.0]]);
        let mut t = LateralTracker::new(&r, 8.0, 10.0);
        assert!(close(t.next([4.0, 1.0]), 1.0));
        assert_eq!(t.next([12.0, 1.0]), None);
    }

    #[test]
    fn lookahead_window_is_bounded() {
        // 2 m segments along x; a frame beside segment 9 (start 18 m) is out of reach from m = 0
        // (window: starts <= 2 + 10 = 12 m), so segment 6 (start 12 m) is the farthest candidate.
        let pts: Vec<[f64; 2]> = (0..=12).map(|i| [2.0 * i as f64, 0.0]).collect();
        let r = route(&pts);
        let mut t = LateralTracker::new(&r, 8.0, 10.0);
        // (19, 0): nearest candidate is segment 6 ending at (14, 0): 5 m away.
        assert!(close(t.next([19.0, 0.0]), 5.0));
        assert_eq!(t.segment(), 6);
        // Now the window reaches 14 + 10 = 24 m: segment 9 is a candidate and is exact.
        assert!(close(t.next([19.0, 0.0]), 0.0));
        assert_eq!(t.segment(), 9);
    }

    #[test]
    fn loop_does_not_jump_to_second_pass() {
        // A lap around a 20 m x 20 m square of 2 m segments, then a second lap shifted 0.1 m
        // north. A frame at y = 0.1 on the first pass is 0.1 m from the first pass and 0 m from the
        // second; the second pass is > 10 m of route length away, so it must not be chosen.
        let mut pts: Vec<[f64; 2]> = Vec::new();
        for lap in 0..2 {
            let dy = 0.1 * lap as f64;
            for i in 0..10 {
                pts.push([2.0 * i as f64, dy]);
            }
            for i in 0..10 {
                pts.push([20.0, 2.0 * i as f64 + dy]);
            }
            for i in 0..10 {
                pts.push([20.0 - 2.0 * i as f64, 20.0 + dy]);
            }
            for i in 0..10 {
                pts.push([0.0, 20.0 - 2.0 * i as f64 + dy]);
            }
        }
        pts.push([0.0, 0.1]);
        let r = route(&pts);
        let mut t = LateralTracker::new(&r, 8.0, 10.0);
        for i in 0..10 {
            let d = t.next([2.0 * i as f64 + 1.0, 0.1]);
            assert!(close(d, 0.1), "{d:?}");
        }
        assert!(
            t.segment() < 10,
            "stayed on the first pass: {}",
            t.segment()
        );
        // Drive the whole first lap; at its end the tracker enters the second lap.
        for i in 0..10 {
            t.next([20.0, 2.0 * i as f64 + 1.0]);
        }
        for i in 0..10 {
            t.next([20.0 - 2.0 * i as f64 - 1.0, 20.0]);
        }
        for i in 0..10 {
            t.next([0.0, 20.0 - 2.0 * i as f64 - 1.0]);
        }
        assert_eq!(t.segment(), 39);
        // Segment 40 runs (0, 0.1) -> (2, 0.1).
        assert!(close(t.next([1.0, -0.2]), 0.3));
        assert_eq!(
            t.segment(),
            40,
            "second pass reached by driving, not by jumping"
        );
    }

    #[test]
    fn figure_eight_crossing() {
        // Route goes east along y = 0 through the crossing at (10, 0), loops north and comes back
        // south through (10, 0) on x = 10. At the crossing the first pass must be kept.
        let mut pts: Vec<[f64; 2]> = (0..=10).map(|i| [2.0 * i as f64, 0.0]).collect(); // to (20,0)
        pts.extend((1..=5).map(|i| [20.0, 2.0 * i as f64])); // to (20,10)
        pts.extend((1..=5).map(|i| [20.0 - 2.0 * i as f64, 10.0])); // to (10,10)
        pts.extend((1..=10).map(|i| [10.0, 10.0 - 2.0 * i as f64])); // south through (10,0)
        let r = route(&pts);
        let mut t = LateralTracker::new(&r, 8.0, 10.0);
        for i in 0..5 {
            t.next([2.0 * i as f64 + 1.0, 0.0]);
        }
        // At (10, 0.5): first pass (segment 5, y = 0) and second pass (x = 10) both at <= 0.5.
        // An unbounded search would jump to the second pass (distance 0 on x = 10).
        let d = t.next([10.0, 0.5]);
        assert!(close(d, 0.5), "{d:?}");
        assert!(t.segment() <= 5, "kept the first pass: {}", t.segment());
    }

    #[test]
    fn later_segment_wins_only_if_strictly_nearer() {
        // Segments 0 and 1 share waypoint (2, 0); a point at (2, 1) is exactly 1 m from both.
        let r = route(&[[0.0, 0.0], [2.0, 0.0], [4.0, 0.0]]);
        let mut t = LateralTracker::new(&r, 8.0, 10.0);
        assert!(close(t.next([2.0, 1.0]), 1.0));
        assert_eq!(t.segment(), 0, "tie keeps m");
        assert!(close(t.next([2.5, 1.0]), 1.0));
        assert_eq!(
            t.segment(),
            1,
            "strictly nearer: (2.5,1) is 1.118 from segment 0"
        );
    }

    #[test]
    fn degenerate_routes() {
        let one = route(&[[5.0, 5.0]]);
        assert_eq!(LateralTracker::new(&one, 8.0, 10.0).next([5.0, 5.0]), None);
        let none = route(&[]);
        assert_eq!(LateralTracker::new(&none, 8.0, 10.0).next([0.0, 0.0]), None);
        // Zero-length segment: distance to the point.
        let z = route(&[[1.0, 1.0], [1.0, 1.0]]);
        assert!(close(
            LateralTracker::new(&z, 8.0, 10.0).next([4.0, 5.0]),
            5.0
        ));
    }

    #[test]
    fn large_coordinates_keep_precision() {
        // 10 km from the origin: a 1 mm offset must still come out as 1 mm.
        let r = route(&[[10_000.0, -9_000.0], [10_002.0, -9_000.0]]);
        let mut t = LateralTracker::new(&r, 8.0, 10.0);
        let d = t.next([10_001.0, -9_000.001]).unwrap();
        assert!((d - 0.001).abs() < 1e-9, "{d}");
    }
}
