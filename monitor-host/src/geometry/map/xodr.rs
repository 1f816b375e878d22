//! Reading an OpenDRIVE file (`roxmltree`) into [`Road`]s and [`Junction`]s, checking what the
//! geometry needs: finite numbers, non-negative lengths, `width` (not `border`) lanes, and links
//! that name roads and junctions of the file.

use std::collections::HashMap;

use roxmltree::Node;

use super::bounds;
use super::cubic::{Cubic, Piecewise};
use super::error::MapError;
use super::reference_line::{Geometry, ReferenceLine, Shape};
use super::road::{Connection, Contact, Junction, Lane, LaneSection, Road, RoadLink};

/// Longest road or geometry accepted (m): a town's roads are far shorter, and the lane network
/// samples every lane every few metres.
pub(crate) const MAX_LENGTH: f64 = 100_000.0;

/// How far a road's geometries may leave a gap, overlap, or end away from the road's length (m).
/// CARLA's towns agree to 1e-13 m; beyond the last geometry the reference line would be an
/// extrapolation that can coil or run away (and make every query on it slow), so a larger
/// mismatch is an error.
pub(crate) const PLAN_TOLERANCE: f64 = 0.1;

/// The roads and junctions of a file, links resolved to indices.
pub(crate) struct Parsed {
    pub roads: Vec<Road>,
    pub junctions: Vec<Junction>,
}

struct Ctx<'a> {
    file: &'a str,
}

impl Ctx<'_> {
    fn err(&self, element: impl Into<String>, problem: impl Into<String>) -> MapError {
        MapError::Invalid {
            file: self.file.to_string(),
            element: element.into(),
            problem: problem.into(),
        }
    }

    /// A required finite number.
    fn num(&self, node: Node, name: &str, element: &dyn Fn() -> String) -> Result<f64, MapError> {
        match node.attribute(name) {
            None => Err(self.err(element(), format!("attribute `{name}` is missing"))),
            Some(text) => match text.trim().parse::<f64>() {
                Ok(v) if v.is_finite() => Ok(v),
                _ => Err(self.err(
                    element(),
                    format!("attribute `{name}` = {text:?} is not a finite number"),
                )),
            },
        }
    }

    /// An optional finite number, `default` when absent.
    fn num_or(
        &self,
        node: Node,
        name: &str,
        default: f64,
        element: &dyn Fn() -> String,
    ) -> Result<f64, MapError> {
        if node.attribute(name).is_some() {
            self.num(node, name, element)
        } else {
            Ok(default)
        }
    }

    fn int(&self, node: Node, name: &str, element: &dyn Fn() -> String) -> Result<i32, MapError> {
        let text = node
            .attribute(name)
            .ok_or_else(|| self.err(element(), format!("attribute `{name}` is missing")))?;
        text.trim().parse::<i32>().map_err(|_| {
            self.err(
                element(),
                format!("attribute `{name}` = {text:?} is not an integer"),
            )
        })
    }

    fn cubics(
        &self,
        parent: Node,
        tag: &'static str,
        start: &str,
        element: &dyn Fn(usize) -> String,
    ) -> Result<Vec<Cubic>, MapError> {
        children(parent, tag)
            .enumerate()
            .map(|(i, n)| {
                let el = || element(i);
                Ok(Cubic {
                    start: self.num(n, start, &el)?,
                    a: self.num_or(n, "a", 0.0, &el)?,
                    b: self.num_or(n, "b", 0.0, &el)?,
                    c: self.num_or(n, "c", 0.0, &el)?,
                    d: self.num_or(n, "d", 0.0, &el)?,
                })
            })
            .collect()
    }
}

fn children<'a, 'i>(node: Node<'a, 'i>, tag: &'static str) -> impl Iterator<Item = Node<'a, 'i>> {
    node.children()
        .filter(move |c| c.is_element() && c.tag_name().name() == tag)
}

fn child<'a, 'i>(node: Node<'a, 'i>, tag: &'static str) -> Option<Node<'a, 'i>> {
    children(node, tag).next()
}

/// Parses the XML text of a map.
pub(crate) fn parse(xml: &str, file: &str) -> Result<Parsed, MapError> {
    let ctx = Ctx { file };
    let doc = roxmltree::Document::parse(xml).map_err(|e| MapError::Xml {
        file: file.to_string(),
        message: format!("{e} (a truncated or damaged file?)"),
    })?;
    let root = doc.root_element();
    if root.tag_name().name() != "OpenDRIVE" {
        return Err(ctx.err(
            format!("root element <{}>", root.tag_name().name()),
            "an OpenDRIVE map starts with <OpenDRIVE>",
        ));
    }
    let road_nodes: Vec<Node> = children(root, "road").collect();
    let junction_nodes: Vec<Node> = children(root, "junction").collect();

    let mut road_index = HashMap::new();
    for (i, r) in road_nodes.iter().enumerate() {
        let id = r.attribute("id").ok_or_else(|| {
            ctx.err(
                format!("road #{i} (in file order)"),
                "attribute `id` is missing",
            )
        })?;
        if road_index.insert(id, i).is_some() {
            return Err(ctx.err(format!("road {id}"), "a second road has the same id"));
        }
    }
    let mut junction_index = HashMap::new();
    for (i, j) in junction_nodes.iter().enumerate() {
        let id = j.attribute("id").ok_or_else(|| {
            ctx.err(
                format!("junction #{i} (in file order)"),
                "attribute `id` is missing",
            )
        })?;
        if junction_index.insert(id, i).is_some() {
            return Err(ctx.err(
                format!("junction {id}"),
                "a second junction has the same id",
            ));
        }
    }

    let mut roads = Vec::with_capacity(road_nodes.len());
    let mut lane_length = 0.0;
    for r in &road_nodes {
        let road = parse_road(&ctx, *r, &road_index, &junction_index)?;
        lane_length += road
            .sections
            .iter()
            .map(|s| {
                (s.s1 - s.s0) * s.left.iter().chain(&s.right).filter(|l| l.driving).count() as f64
            })
            .sum::<f64>();
        if lane_length > bounds::MAX_LANE_LENGTH {
            return Err(ctx.err(
                format!("road {}", road.id),
                format!(
                    "the driving lanes up to this road are {:.0} km long, more than {:.0} km \
                     (the largest CARLA town has under 100 km)",
                    lane_length / 1000.0,
                    bounds::MAX_LANE_LENGTH / 1000.0
                ),
            ));
        }
        roads.push(road);
    }
    let mut junctions = Vec::with_capacity(junction_nodes.len());
    for j in &junction_nodes {
        junctions.push(parse_junction(&ctx, *j, &road_index)?);
    }
    Ok(Parsed { roads, junctions })
}

fn contact(ctx: &Ctx, node: Node, element: &str) -> Result<Contact, MapError> {
    match node.attribute("contactPoint") {
        Some("start") => Ok(Contact::Start),
        Some("end") => Ok(Contact::End),
        other => Err(ctx.err(
            element,
            format!("contactPoint {other:?} is neither \"start\" nor \"end\""),
        )),
    }
}

fn parse_link(
    ctx: &Ctx,
    node: Node,
    road_id: &str,
    which: &str,
    roads: &HashMap<&str, usize>,
    junctions: &HashMap<&str, usize>,
) -> Result<Option<RoadLink>, MapError> {
    let element = format!("road {road_id}, {which}");
    let target = node.attribute("elementId").unwrap_or("");
    match node.attribute("elementType") {
        Some("road") => {
            let road = *roads.get(target).ok_or_else(|| {
                ctx.err(
                    &element,
                    format!("links to road {target:?}, which is not in the map"),
                )
            })?;
            Ok(Some(RoadLink::Road {
                road,
                contact: contact(ctx, node, &element)?,
            }))
        }
        Some("junction") => {
            let junction = *junctions.get(target).ok_or_else(|| {
                ctx.err(
                    &element,
                    format!("links to junction {target:?}, which is not in the map"),
                )
            })?;
            Ok(Some(RoadLink::Junction { junction }))
        }
        // Other element types (e.g. a virtual junction of 1.8) carry no lane links here.
        _ => Ok(None),
    }
}

fn parse_road(
    ctx: &Ctx,
    node: Node,
    roads: &HashMap<&str, usize>,
    junctions: &HashMap<&str, usize>,
) -> Result<Road, MapError> {
    let id = node.attribute("id").unwrap_or_default().to_string();
    let rid = id.as_str();
    let here = || format!("road {rid}");
    let length = ctx.num(node, "length", &here)?;
    if length < 0.0 {
        return Err(ctx.err(here(), format!("negative length {length}")));
    }
    if length > MAX_LENGTH {
        return Err(ctx.err(
            here(),
            format!("length {length} m is longer than {MAX_LENGTH} m"),
        ));
    }
    let junction = match node.attribute("junction").map(str::trim) {
        None | Some("-1") | Some("") => None,
        Some(j) if !junctions.contains_key(j) => {
            return Err(ctx.err(
                here(),
                format!("junction=\"{j}\" names no <junction> of the map (-1: not in a junction)"),
            ))
        }
        Some(j) => Some(j.to_string()),
    };

    let (mut predecessor, mut successor) = (None, None);
    if let Some(link) = child(node, "link") {
        if let Some(p) = child(link, "predecessor") {
            predecessor = parse_link(ctx, p, rid, "predecessor", roads, junctions)?;
        }
        if let Some(s) = child(link, "successor") {
            successor = parse_link(ctx, s, rid, "successor", roads, junctions)?;
        }
    }

    // Reference line.
    let mut geometries = Vec::new();
    // (s, length, index) of each geometry, to check that they tile the road.
    let mut spans = Vec::new();
    if let Some(pv) = child(node, "planView") {
        for (gi, g) in children(pv, "geometry").enumerate() {
            let el = || format!("road {rid}, geometry {gi}");
            let s0 = ctx.num(g, "s", &el)?;
            let x = ctx.num(g, "x", &el)?;
            let y = ctx.num(g, "y", &el)?;
            let hdg = ctx.num(g, "hdg", &el)?;
            let glen = ctx.num(g, "length", &el)?;
            if glen < 0.0 {
                return Err(ctx.err(el(), format!("negative length {glen}")));
            }
            if glen > MAX_LENGTH {
                return Err(ctx.err(
                    el(),
                    format!("length {glen} m is longer than {MAX_LENGTH} m"),
                ));
            }
            let kind = g.children().find(|c| c.is_element()).ok_or_else(|| {
                ctx.err(el(), "has no shape (line, arc, spiral, poly3, paramPoly3)")
            })?;
            let shape = match kind.tag_name().name() {
                "line" => Shape::Line,
                "arc" => {
                    let k = ctx.num(kind, "curvature", &el)?;
                    if let Some(why) = bounds::curvature(k, k, glen) {
                        return Err(ctx.err(el(), why));
                    }
                    Shape::Arc { k }
                }
                "spiral" => {
                    let k0 = ctx.num(kind, "curvStart", &el)?;
                    let k1 = ctx.num(kind, "curvEnd", &el)?;
                    if let Some(why) = bounds::curvature(k0, k1, glen) {
                        return Err(ctx.err(el(), why));
                    }
                    Shape::spiral(hdg, glen, k0, k1)
                }
                "poly3" => {
                    let v = [
                        ctx.num(kind, "a", &el)?,
                        ctx.num(kind, "b", &el)?,
                        ctx.num(kind, "c", &el)?,
                        ctx.num(kind, "d", &el)?,
                    ];
                    Shape::poly([0.0, 1.0, 0.0, 0.0], v, glen)
                }
                "paramPoly3" => {
                    let mut c = [0.0; 8];
                    for (k, name) in ["aU", "bU", "cU", "dU", "aV", "bV", "cV", "dV"]
                        .iter()
                        .enumerate()
                    {
                        c[k] = ctx.num(kind, name, &el)?;
                    }
                    let p_end = match kind.attribute("pRange") {
                        Some("normalized") => 1.0,
                        None | Some("arcLength") => glen,
                        Some(other) => {
                            return Err(ctx.err(
                                el(),
                                format!("pRange {other:?} is neither \"arcLength\" nor \"normalized\""),
                            ))
                        }
                    };
                    Shape::poly([c[0], c[1], c[2], c[3]], [c[4], c[5], c[6], c[7]], p_end)
                }
                other => {
                    return Err(ctx.err(
                        el(),
                        format!("unknown geometry <{other}> (expected line, arc, spiral, poly3 or paramPoly3)"),
                    ))
                }
            };
            geometries.push(Geometry::new(s0, x, y, hdg, shape));
            spans.push((s0, glen, gi));
        }
    }
    if geometries.is_empty() {
        return Err(ctx.err(here(), "has no <planView> geometry"));
    }
    geometries.sort_by(|a, b| a.s0.total_cmp(&b.s0));
    spans.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut end = 0.0;
    for &(s0, glen, gi) in &spans {
        if (s0 - end).abs() > PLAN_TOLERANCE {
            return Err(ctx.err(
                format!("road {rid}, geometry {gi}"),
                format!(
                    "starts at s = {} but the reference line so far ends at s = {end} \
                     (geometries must follow each other within {PLAN_TOLERANCE} m)",
                    s0
                ),
            ));
        }
        end = s0 + glen;
    }
    if (length - end).abs() > PLAN_TOLERANCE {
        return Err(ctx.err(
            here(),
            format!(
                "length {length} m, but its geometries end at s = {end} \
                 (they must agree within {PLAN_TOLERANCE} m)"
            ),
        ));
    }

    let elevation = match child(node, "elevationProfile") {
        Some(ep) => ctx.cubics(ep, "elevation", "s", &|i| {
            format!("road {rid}, elevation {i}")
        })?,
        None => Vec::new(),
    };

    let lanes = child(node, "lanes").ok_or_else(|| ctx.err(here(), "has no <lanes>"))?;
    let lane_offset = ctx.cubics(lanes, "laneOffset", "s", &|i| {
        format!("road {rid}, laneOffset {i}")
    })?;
    let mut sections = Vec::new();
    for (si, sec) in children(lanes, "laneSection").enumerate() {
        let el = || format!("road {rid}, lane section {si}");
        let s0 = ctx.num(sec, "s", &el)?;
        if let Some(prev) = sections.last() {
            let prev: &LaneSection = prev;
            if s0 < prev.s0 {
                return Err(ctx.err(
                    el(),
                    format!(
                        "starts at s = {s0}, before the previous section ({})",
                        prev.s0
                    ),
                ));
            }
        }
        let mut left = Vec::new();
        let mut right = Vec::new();
        for (side_tag, positive) in [("left", true), ("right", false)] {
            let Some(side) = children(sec, side_tag).next() else {
                continue;
            };
            let n = children(side, "lane").count();
            if n > bounds::MAX_LANES_PER_SIDE {
                return Err(ctx.err(
                    el(),
                    format!(
                        "{n} lanes on the <{side_tag}> side, more than {} (no road has that many)",
                        bounds::MAX_LANES_PER_SIDE
                    ),
                ));
            }
            for lane in children(side, "lane") {
                let id = ctx.int(lane, "id", &el)?;
                let lel = || format!("road {rid}, lane section {si}, lane {id}");
                if (id > 0) != positive || id == 0 {
                    return Err(ctx.err(lel(), format!("lane id {id} on the <{side_tag}> side")));
                }
                let widths = ctx.cubics(lane, "width", "sOffset", &|i| {
                    format!("road {rid}, lane section {si}, lane {id}, width {i}")
                })?;
                if widths.is_empty() && child(lane, "border").is_some() {
                    return Err(ctx.err(
                        lel(),
                        "the lane is given by <border> records; only <width> records are supported (convert its borders to widths)",
                    ));
                }
                let (mut predecessor, mut successor) = (None, None);
                if let Some(link) = child(lane, "link") {
                    if let Some(p) = child(link, "predecessor") {
                        predecessor = Some(ctx.int(p, "id", &lel)?);
                    }
                    if let Some(s) = child(link, "successor") {
                        successor = Some(ctx.int(s, "id", &lel)?);
                    }
                }
                let driving = lane
                    .attribute("type")
                    .is_some_and(|t| t.eq_ignore_ascii_case("driving"));
                let l = Lane {
                    id,
                    driving,
                    widths: Piecewise::new(widths),
                    predecessor,
                    successor,
                };
                if positive {
                    left.push(l);
                } else {
                    right.push(l);
                }
            }
        }
        left.sort_by_key(|l| l.id);
        right.sort_by_key(|l| -l.id);
        for side in [&left, &right] {
            if let Some(w) = side.windows(2).find(|w| w[0].id == w[1].id) {
                return Err(ctx.err(el(), format!("two lanes have id {}", w[0].id)));
            }
        }
        sections.push(LaneSection {
            s0,
            s1: length,
            left,
            right,
        });
    }
    for i in 1..sections.len() {
        sections[i - 1].s1 = sections[i].s0;
    }
    // A driving lane wider than any road's would make its slack (nearly) infinite.
    for (si, sec) in sections.iter().enumerate() {
        for lane in sec.left.iter().chain(&sec.right).filter(|l| l.driving) {
            let records = &lane.widths.0;
            for (wi, w) in records.iter().enumerate() {
                let to = records.get(wi + 1).map_or(sec.s1 - sec.s0, |n| n.start);
                let widest = bounds::max_abs(w, w.start, to.max(w.start));
                if widest > bounds::MAX_LANE_WIDTH {
                    return Err(ctx.err(
                        format!(
                            "road {rid}, lane section {si}, lane {}, width {wi}",
                            lane.id
                        ),
                        format!(
                            "{widest} m wide, more than {} m (no driving lane is that wide)",
                            bounds::MAX_LANE_WIDTH
                        ),
                    ));
                }
            }
        }
    }

    Ok(Road {
        id: id.clone(),
        length,
        junction,
        reference: ReferenceLine { geometries },
        elevation: Piecewise::new(elevation),
        lane_offset: Piecewise::new(lane_offset),
        sections,
        predecessor,
        successor,
        left_hand: node.attribute("rule") == Some("LHT"),
    })
}

fn parse_junction(
    ctx: &Ctx,
    node: Node,
    roads: &HashMap<&str, usize>,
) -> Result<Junction, MapError> {
    let id = node.attribute("id").unwrap_or_default();
    let mut connections = Vec::new();
    for (ci, c) in children(node, "connection").enumerate() {
        let cid = c.attribute("id").unwrap_or("?");
        let el = format!("junction {id}, connection {cid} (#{ci})");
        let road = |attr: &str| -> Result<usize, MapError> {
            let r = c.attribute(attr).unwrap_or("");
            roads
                .get(r)
                .copied()
                .ok_or_else(|| ctx.err(&el, format!("{attr} {r:?} is not a road of the map")))
        };
        let incoming = road("incomingRoad")?;
        let connecting = road("connectingRoad")?;
        let contact = contact(ctx, c, &el)?;
        let mut lane_links = Vec::new();
        for l in children(c, "laneLink") {
            let f = || el.clone();
            lane_links.push((ctx.int(l, "from", &f)?, ctx.int(l, "to", &f)?));
        }
        connections.push(Connection {
            incoming,
            connecting,
            contact,
            lane_links,
        });
    }
    Ok(Junction { connections })
}
