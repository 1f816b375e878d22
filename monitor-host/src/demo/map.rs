//! The demo town's OpenDRIVE map, of our own making: the demo road (eastbound lanes -1 and -2,
//! westbound lane 1, 3.5 m each) through a junction at 60-90 m from the demo origin, where a
//! straight connecting road continues east and a right turn leaves to the south. Every demo
//! route drives along it; the junction route's XML leaves the junction out, as real route files
//! do, and the map fills the gap.

use std::fmt::Write as _;

/// The demo town's name (the records' `town_name`, the XML `town`, the map file `DemoTown.xodr`).
pub const TOWN: &str = "DemoTown";
/// Where the junction starts and ends, m east of the demo origin.
pub const JUNCTION: (f64, f64) = (60.0, 90.0);
/// Length of the road east of the junction (long enough for the large run's routes), m.
const EAST_LENGTH: f64 = 4_000.0;
/// Radius of the right turn, m.
const TURN_RADIUS: f64 = 12.0;

/// A lane of width 3.5 m with optional lane links.
fn lane(id: i32, pred: Option<i32>, succ: Option<i32>) -> String {
    let mut link = String::new();
    if let Some(p) = pred {
        let _ = write!(link, "<predecessor id=\"{p}\"/>");
    }
    if let Some(s) = succ {
        let _ = write!(link, "<successor id=\"{s}\"/>");
    }
    if !link.is_empty() {
        link = format!("<link>{link}</link>");
    }
    format!(
        "<lane id=\"{id}\" type=\"driving\" level=\"false\">{link}\
         <width sOffset=\"0\" a=\"3.5\" b=\"0\" c=\"0\" d=\"0\"/></lane>"
    )
}

/// One road of the map, written by [`Road::xml`].
struct Road<'a> {
    id: u32,
    /// The junction the road belongs to, -1 for none.
    junction: i32,
    /// The inner elements of `<link>`.
    links: &'a str,
    /// Start of the reference line and its heading: x, y, hdg.
    start: (f64, f64, f64),
    length: f64,
    /// The planView's inner element (`<line/>`, `<arc .../>`).
    geometry: &'a str,
    left: &'a [String],
    right: &'a [String],
}

impl Road<'_> {
    fn xml(&self) -> String {
        let Road {
            id,
            junction,
            links,
            start: (x, y, hdg),
            length,
            geometry,
            left,
            right,
        } = self;
        format!(
            "  <road name=\"Road {id}\" length=\"{length}\" id=\"{id}\" junction=\"{junction}\">\n\
             \x20   <link>{links}</link>\n\
             \x20   <planView><geometry s=\"0\" x=\"{x}\" y=\"{y}\" hdg=\"{hdg}\" length=\"{length}\">{geometry}</geometry></planView>\n\
             \x20   <lanes><laneSection s=\"0\">\n\
             \x20     <left>{}</left>\n\
             \x20     <center><lane id=\"0\" type=\"none\" level=\"false\"/></center>\n\
             \x20     <right>{}</right>\n\
             \x20   </laneSection></lanes>\n\
             \x20 </road>\n",
            left.concat(),
            right.concat()
        )
    }
}

/// The map's text. `origin` is the demo origin in CARLA coordinates: lane -1's centre line runs
/// through it eastwards (OpenDRIVE's y is CARLA's negated, so the reference line lies 1.75 m to
/// CARLA's -y of it).
pub fn xodr(origin: [f64; 2]) -> String {
    let (x0, y0) = (origin[0], -origin[1] + 1.75);
    let (j0, j1) = JUNCTION;
    let west = 50.0 + j0;
    let r = TURN_RADIUS;
    let turn = std::f64::consts::FRAC_PI_2 * r;
    let to = |e: &str, id: u32, contact: &str| {
        format!("<{e} elementType=\"road\" elementId=\"{id}\" contactPoint=\"{contact}\"/>")
    };
    let junction = |e: &str| format!("<{e} elementType=\"junction\" elementId=\"100\"/>");
    let mut s = String::from(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<OpenDRIVE>\n  \
         <header revMajor=\"1\" revMinor=\"4\" name=\"DemoTown\" version=\"1\" vendor=\"sds demo\"/>\n",
    );
    // Road 1: from 50 m west of the origin to the junction.
    s += &Road {
        id: 1,
        junction: -1,
        links: &junction("successor"),
        start: (x0 - 50.0, y0, 0.0),
        length: west,
        geometry: "<line/>",
        left: &[lane(1, None, None)],
        right: &[lane(-1, None, None), lane(-2, None, None)],
    }
    .xml();
    // Road 2: east of the junction.
    s += &Road {
        id: 2,
        junction: -1,
        links: &junction("predecessor"),
        start: (x0 + j1, y0, 0.0),
        length: EAST_LENGTH,
        geometry: "<line/>",
        left: &[lane(1, None, None)],
        right: &[lane(-1, None, None), lane(-2, None, None)],
    }
    .xml();
    // Road 3: south of the junction, after the right turn.
    s += &Road {
        id: 3,
        junction: -1,
        links: &junction("predecessor"),
        start: (x0 + j0 + r, y0 - r, -std::f64::consts::FRAC_PI_2),
        length: 50.0,
        geometry: "<line/>",
        left: &[lane(1, None, None)],
        right: &[lane(-1, None, None)],
    }
    .xml();
    // Road 10: straight through the junction.
    s += &Road {
        id: 10,
        junction: 100,
        links: &(to("predecessor", 1, "end") + &to("successor", 2, "start")),
        start: (x0 + j0, y0, 0.0),
        length: j1 - j0,
        geometry: "<line/>",
        left: &[],
        right: &[lane(-1, Some(-1), Some(-1)), lane(-2, Some(-2), Some(-2))],
    }
    .xml();
    // Road 11: the right turn from lane -1.
    s += &Road {
        id: 11,
        junction: 100,
        links: &(to("predecessor", 1, "end") + &to("successor", 3, "start")),
        start: (x0 + j0, y0, 0.0),
        length: turn,
        geometry: &format!("<arc curvature=\"{}\"/>", -1.0 / r),
        left: &[],
        right: &[lane(-1, Some(-1), Some(-1))],
    }
    .xml();
    s += "  <junction id=\"100\" name=\"demo junction\">\n\
          \x20   <connection id=\"0\" incomingRoad=\"1\" connectingRoad=\"10\" contactPoint=\"start\">\
          <laneLink from=\"-1\" to=\"-1\"/><laneLink from=\"-2\" to=\"-2\"/></connection>\n\
          \x20   <connection id=\"1\" incomingRoad=\"1\" connectingRoad=\"11\" contactPoint=\"start\">\
          <laneLink from=\"-1\" to=\"-1\"/></connection>\n  </junction>\n</OpenDRIVE>\n";
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::map::Map;

    #[test]
    fn the_demo_map_reads_and_fills_the_junction_gap() {
        let origin = [1520.0, -3310.0];
        let map = Map::parse(&xodr(origin), "DemoTown.xodr").unwrap();
        // Lane -1's centre runs through the origin, 3.5 m wide.
        let p = map.project(origin[0] + 10.0, origin[1], 0.0).unwrap();
        assert!(
            p.distance_2d < 1e-9 && (p.width - 3.5).abs() < 1e-12,
            "{p:?}"
        );
        assert_eq!((map.road_id(p.lane.road), p.lane.lane), ("1", -1));
        // Inside the junction, on the straight connecting road.
        let p = map.project(origin[0] + 75.0, origin[1], 0.0).unwrap();
        assert!(p.junction && map.road_id(p.lane.road) == "10", "{p:?}");
        // The gap 56 m -> 94 m is filled straight through the junction.
        let chain = map
            .fill_gap(
                [origin[0] + 56.0, origin[1], 0.0],
                [origin[0] + 94.0, origin[1], 0.0],
            )
            .unwrap();
        assert!(chain.iter().all(|q| (q[1] - origin[1]).abs() < 1e-9));
        // The right turn ends on road 3, heading south (CARLA +y).
        let q = [origin[0] + 60.0 + 12.0 - 1.75, origin[1] + 20.0, 0.0];
        let p = map.project(q[0], q[1], 0.0).unwrap();
        assert_eq!(map.road_id(p.lane.road), "3");
    }
}
