//! Issue 40 (performance): what the speed and memory work must not change.

use monitor_host::input::metric_info::{
    parse_metric_info, parse_metric_info_fast, parse_metric_info_serde,
};
use monitor_host::input::route_xml::parse_route_xml;

/// One frame in `json.dump(indent=4)` layout with the given six vectors' texts.
fn frame_file(vectors: [[&str; 3]; 6]) -> String {
    let names = [
        "acceleration",
        "angular_velocity",
        "forward_vector",
        "right_vector",
        "location",
        "rotation",
    ];
    let fields: Vec<String> = names
        .iter()
        .zip(vectors)
        .map(|(n, v)| {
            format!(
                "        \"{n}\": [\n            {}\n        ]",
                v.join(",\n            ")
            )
        })
        .collect();
    format!("{{\n    \"1\": {{\n{}\n    }}\n}}", fields.join(",\n"))
}

const PLAIN: [[&str; 3]; 6] = [
    [
        "0.49865996837615967",
        "-0.0003108195378445089",
        "-0.0005016197683289647",
    ],
    [
        "0.007959960028529167",
        "-0.0014821309596300125",
        "-4.4775766582461074e-05",
    ],
    [
        "0.9999997019767761",
        "0.0007839985191822052",
        "3.1713909265818074e-05",
    ],
    [
        "-0.0007839985191822052",
        "0.9999997019767761",
        "5.6008640967775136e-05",
    ],
    ["1520.0", "-3310.0", "0.0017863388638943434"],
    [
        "-0.0015013996744528413",
        "0.04491981118917465",
        "0.006896458100527525",
    ],
];

/// The scanner converts only the 10 numbers a frame keeps; the other 5 of the required vectors
/// must still be finite, so an overflowing literal there is still the error serde_json's path
/// names, and a large finite one is still read by the fast path.
#[test]
fn i40_unconverted_components_are_still_checked_finite() {
    let plain = frame_file(PLAIN);
    let fast = parse_metric_info_fast(plain.as_bytes()).expect("the fast path reads it");
    assert_eq!(Some(fast), parse_metric_info_serde(plain.as_bytes()).ok());
    // (field, component) pairs that no frame keeps.
    for (f, k) in [(0, 2), (1, 0), (1, 1), (2, 2), (3, 2)] {
        for (text, finite) in [
            ("1e999", false),
            ("-1e309", false),
            ("1e308", true),
            ("9e-999", true),
        ] {
            let mut v = PLAIN;
            v[f][k] = text;
            let file = frame_file(v);
            let fast = parse_metric_info_fast(file.as_bytes());
            let serde = parse_metric_info_serde(file.as_bytes());
            assert_eq!(fast.is_some(), finite, "{text} at {f}.{k}");
            let both = parse_metric_info(file.as_bytes());
            match (&both, &serde) {
                (Ok(a), Ok(b)) => assert_eq!(a, b, "{text} at {f}.{k}"),
                (Err(a), Err(b)) => assert_eq!(a.to_string(), b.to_string(), "{text} at {f}.{k}"),
                _ => panic!("{text} at {f}.{k}: {both:?} vs {serde:?}"),
            }
            assert_eq!(serde.is_ok(), finite, "{text} at {f}.{k}");
        }
    }
}

/// The route XML is held for the whole run: its waypoints without the slack of growing.
#[test]
fn i40_route_waypoints_are_held_without_growth_slack() {
    let positions: String = (0..37)
        .map(|i| format!("<position x=\"{i}.0\" y=\"0.0\" z=\"0.0\"/>"))
        .collect();
    let xml = format!(
        "<routes><route id=\"3\" town=\"Town01\"><waypoints>{positions}</waypoints></route></routes>"
    );
    let set = parse_route_xml(&xml).unwrap();
    let route = set.get("3").unwrap();
    assert_eq!(route.waypoints.len(), 37);
    assert_eq!(route.waypoints.capacity(), 37);
    assert_eq!(route.heights.capacity(), 37);
}
