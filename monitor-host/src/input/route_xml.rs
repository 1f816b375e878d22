//! The Bench2Drive route XML (docs/SCORE.md §2.3): `<routes><route id town><waypoints>
//! <position x y z/>...`, read with a streaming XML reader into a [`RouteSet`]. Its waypoints
//! are the reference of the lateral error ([`crate::geometry::lateral`]).
//!
//! ```
//! use monitor_host::input::route_xml::parse_route_xml;
//!
//! let set = parse_route_xml(r#"<routes><route id="7" town="Town01"><waypoints>
//!     <position x="0" y="0" z="0"/><position x="2" y="0" z="0"/>
//!   </waypoints></route></routes>"#)?;
//! let route = set.get("7").expect("route 7");
//! assert_eq!(route.town, "Town01");
//! assert_eq!(route.waypoints, vec![[0.0, 0.0], [2.0, 0.0]]);
//! # Ok::<(), monitor_host::input::route_xml::RouteError>(())
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
    /// The waypoints' heights (`z`, 0 when absent), same order: maps use them to choose the
    /// lane of a point under an overpass (docs/SCORE.md §14.3).
    pub heights: Vec<f64>,
    /// The `type` attribute of the route's first `<scenario>` (inside `<scenarios>`): the
    /// scenario type Bench2Drive's ability rates read (docs/SCORE.md §10.1).
    pub scenario_type: Option<String>,
}

impl RouteRef {
    /// The waypoints with their heights, `[x, y, z]` (the dense route's input, docs/SCORE.md §14.3).
    pub fn waypoints_3d(&self) -> Vec<[f64; 3]> {
        self.waypoints
            .iter()
            .zip(self.heights.iter().chain(std::iter::repeat(&0.0)))
            .map(|(p, z)| [p[0], p[1], *z])
            .collect()
    }
}

/// Why a route file or one of its routes cannot be used. Names the file and the route id.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum RouteError {
    /// The file cannot be read.
    #[error("cannot read route file {}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The OS error.
        #[source]
        source: IoError,
    },
    /// The XML is not well formed (the whole set is rejected).
    #[error("{file}: malformed XML at line {line} (byte {offset}): {message}")]
    Xml {
        /// The file (`<memory>` for [`parse_route_xml`]).
        file: String,
        /// 1-based line of the error.
        line: usize,
        /// Byte offset of the error.
        offset: u64,
        /// The parser's message.
        message: String,
    },
    /// A route file without a single `<route>` element: most likely another file given as
    /// `--routes` (a results JSON reads as XML text without elements). Refused: it would make
    /// every record a foreign route.
    #[error(
        "{file}: holds no route: not a route XML? (routes takes a Bench2Drive route file: \
         <routes><route id=\"..\" town=\"..\"><waypoints><position x y z/>...)"
    )]
    NoRoutes {
        /// The file.
        file: String,
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
    /// A route with a single waypoint: no segment, so no lateral error.
    #[error("{file}: route {route}: a single waypoint (a reference needs at least 2)")]
    SingleWaypoint {
        /// The file.
        file: String,
        /// The route id.
        route: String,
    },
    /// Two routes with the same id: which one is the reference is unknown, so neither is used.
    #[error("{file}: route {route}: id appears twice (ambiguous: neither copy is used)")]
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

/// An OS error, shareable so that [`RouteError`] can be cloned and compared (by kind and text).
#[derive(Debug, Clone)]
pub struct IoError(pub std::sync::Arc<std::io::Error>);

impl PartialEq for IoError {
    fn eq(&self, other: &Self) -> bool {
        self.0.kind() == other.0.kind() && self.0.to_string() == other.0.to_string()
    }
}

impl std::fmt::Display for IoError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.0.fmt(f)
    }
}

impl std::error::Error for IoError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        self.0.source()
    }
}

/// The routes of one XML file, by id.
///
/// Routes that cannot be used (no waypoints, a bad coordinate) do not stop the set from loading:
/// [`RouteSet::get`] skips them and [`RouteSet::get_checked`] says why. A duplicated id is
/// unusable too (ambiguous) and listed in [`RouteSet::problems`].
#[derive(Debug, Clone, Default)]
pub struct RouteSet {
    file: String,
    routes: Vec<RouteRef>,
    /// Per route (same index): why it is unusable.
    broken: Vec<Option<RouteError>>,
    index: HashMap<String, usize>,
    problems: Vec<RouteError>,
}

impl RouteRef {
    /// True when every segment is longer than `gap_max`: every segment is a junction gap, so
    /// the lateral error is unknown on the whole route.
    ///
    /// ```
    /// use monitor_host::input::route_xml::RouteRef;
    /// let r = RouteRef { waypoints: vec![[0.0, 0.0], [10.0, 0.0], [20.0, 0.0]], ..Default::default() };
    /// assert!(r.all_gaps(8.0));
    /// assert!(!r.all_gaps(10.0));
    /// ```
    pub fn all_gaps(&self, gap_max: f64) -> bool {
        self.waypoints.len() >= 2
            && self.waypoints.windows(2).all(|w| {
                let (dx, dy) = (w[1][0] - w[0][0], w[1][1] - w[0][1]);
                (dx * dx + dy * dy).sqrt() > gap_max
            })
    }
}

impl RouteSet {
    /// The usable route with this XML id (at least one waypoint, all coordinates valid).
    pub fn get(&self, xml_id: &str) -> Option<&RouteRef> {
        self.get_checked(xml_id).ok()
    }

    /// The route with this XML id, or why it cannot be used (naming file and route).
    ///
    /// # Errors
    /// [`RouteError::NotFound`], [`RouteError::NoWaypoints`], [`RouteError::SingleWaypoint`],
    /// [`RouteError::BadWaypoint`] or [`RouteError::DuplicateId`].
    pub fn get_checked(&self, xml_id: &str) -> Result<&RouteRef, RouteError> {
        let Some(&i) = self.index.get(xml_id) else {
            return Err(RouteError::NotFound {
                file: self.file.clone(),
                route: xml_id.to_string(),
            });
        };
        if let Some(dup) = self
            .problems
            .iter()
            .find(|p| matches!(p, RouteError::DuplicateId { route, .. } if route == xml_id))
        {
            return Err(dup.clone());
        }
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

    /// The file name used in error messages (`<memory>` for [`parse_route_xml`]).
    pub fn file(&self) -> &str {
        &self.file
    }
}

/// Loads a route XML file (see [`parse_route_xml`]).
///
/// # Errors
/// [`RouteError::Io`] if unreadable, [`RouteError::NoRoutes`] if it holds no `<route>` (a
/// results JSON given as `--routes`), otherwise as [`parse_route_xml`] (naming this file).
pub fn read_route_xml(path: &Path) -> Result<RouteSet, RouteError> {
    let set = read_any(path)?;
    if set.routes.is_empty() {
        return Err(RouteError::NoRoutes {
            file: path.display().to_string(),
        });
    }
    Ok(set)
}

/// [`read_route_xml`] without the check that the file holds a route.
fn read_any(path: &Path) -> Result<RouteSet, RouteError> {
    let bytes = crate::input::read::read_input(path, crate::input::read::FileKind::RouteXml)
        .map_err(|source| RouteError::Io {
            path: path.to_path_buf(),
            source: IoError(std::sync::Arc::new(source)),
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
/// Reads every `<route id town>` element, the `<position x y z>` elements directly inside its
/// `<waypoints>` and the `type` of its first `<scenarios><scenario>`; everything else (trigger
/// points, scenario parameters, weathers) is skipped.
///
/// # Errors
/// [`RouteError::Xml`] for malformed XML (with line and byte offset), [`RouteError::MissingId`]
/// for a route without id. Per-route problems do not fail the set (see [`RouteSet`]).
pub fn parse_route_xml(xml: &str) -> Result<RouteSet, RouteError> {
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
    if done.error.is_none() && done.route.waypoints.len() == 1 {
        done.error = Some(RouteError::SingleWaypoint {
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
    // Kept for the whole run: without the slack of growing (up to half of it, ~19 KB a route of
    // the 220-route demo).
    done.route.waypoints.shrink_to_fit();
    done.route.heights.shrink_to_fit();
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
                    ..RouteRef::default()
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
        b"scenario" => {
            if let Some(o) = open.as_mut() {
                if o.depth + 2 == depth && o.route.scenario_type.is_none() {
                    o.route.scenario_type = attr_string(reader, e, b"type")
                        .map_err(|m| xml_error_at(reader, file, m))?;
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
    let mut z = 0.0;
    for a in e.attributes() {
        let a = a.map_err(|err| xml_error_at(reader, file, err.to_string()))?;
        let slot = match a.key.as_ref() {
            b"x" => 0,
            b"y" => 1,
            b"z" => {
                // A height only helps choose a lane: an unreadable one is taken as 0.
                let text = std::str::from_utf8(&a.value).unwrap_or("");
                z = text
                    .trim()
                    .parse::<f64>()
                    .ok()
                    .filter(|v| v.is_finite())
                    .unwrap_or(0.0);
                continue;
            }
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
        [Some(x), Some(y)] => {
            o.route.waypoints.push([x, y]);
            o.route.heights.push(z);
        }
        _ => {
            let missing = if xy[0].is_none() { "x" } else { "y" };
            o.bad_waypoint(file, index, format!("attribute {missing} missing"));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_routes_and_skips_other_positions() {
        let set = parse_route_xml(
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
        assert_eq!(r1.heights, vec![364.9, 364.8]);
        assert_eq!(r1.waypoints_3d()[1], [-497.6, 3670.9, 364.8]);
        assert_eq!(r1.scenario_type.as_deref(), Some("A"));
        let r2 = set.iter().nth(1).unwrap();
        assert_eq!(r2.scenario_type, None);
        assert_eq!(r2.town, "Town&X");
        assert_eq!(r2.waypoints, vec![[5.0, 6.0]]);
        assert_eq!(r2.scenario_type, None);
        // A single waypoint is no reference (no segment), and says so.
        assert!(set.get("2").is_none());
        assert_eq!(
            set.get_checked("2").unwrap_err().to_string(),
            "<memory>: route 2: a single waypoint (a reference needs at least 2)"
        );
        assert!(set.get("3").is_none());
        assert_eq!(set.problems().len(), 1);
        assert_eq!(
            set.get_checked("3").unwrap_err().to_string(),
            "<memory>: route 3: not found"
        );
    }

    #[test]
    fn route_without_waypoints_keeps_the_set() {
        let set = parse_route_xml(
            r#"<routes><route id="9" town="T"><waypoints></waypoints></route>
               <route id="10" town="T"/>
               <route id="11" town="T"><waypoints><position x="0" y="0"/><position x="1" y="0"/></waypoints></route></routes>"#,
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
        let set = parse_route_xml(
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
        // Ambiguous: neither copy is used, and the lookup says why.
        assert!(set.get("3").is_none());
        let why = "<memory>: route 3: id appears twice (ambiguous: neither copy is used)";
        assert_eq!(set.problems().last().unwrap().to_string(), why);
        assert_eq!(set.get_checked("3").unwrap_err().to_string(), why);
    }

    #[test]
    fn malformed_xml_names_position() {
        let e = parse_route_xml(
            "<routes>\n<route id=\"1\" town=\"T\">\n<waypoints>\n</route></routes>",
        )
        .unwrap_err();
        let s = e.to_string();
        assert!(s.starts_with("<memory>: malformed XML at line 4 "), "{s}");
        let e = parse_route_xml("<routes><route id=\"1\">")
            .unwrap_err()
            .to_string();
        assert!(e.contains("malformed XML"), "{e}");
        let e = parse_route_xml("<routes><route town=\"T\"/></routes>").unwrap_err();
        assert_eq!(
            e.to_string(),
            "<memory>: route #1 (1-based) has no id attribute"
        );
        let e = read_route_xml(Path::new("/nonexistent/routes.xml")).unwrap_err();
        assert!(e
            .to_string()
            .starts_with("cannot read route file /nonexistent/routes.xml: "));
    }

    #[test]
    fn load_names_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("r.xml");
        std::fs::write(&p, "<routes><route id=\"4\" town=\"T\"></route></routes>").unwrap();
        let set = read_route_xml(&p).unwrap();
        let s = set.get_checked("4").unwrap_err().to_string();
        assert_eq!(s, format!("{}: route 4: no waypoints", p.display()));
    }
}
