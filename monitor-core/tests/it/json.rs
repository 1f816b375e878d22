//! JSON without a heap (serde-json-core): frames in, events and summaries out, byte-exact.

use monitor_core::json::{decode_frame, encode, JsonError};
use monitor_core::{
    Band, CollisionVerdict, Collisions, ComfortVerdict, Event, Failures, Field, Frame, FrameError,
    LateralVerdict, RouteSummary,
};

fn enc<T: serde::Serialize>(v: &T) -> String {
    let mut buf = [0u8; 1024];
    let n = encode(v, &mut buf).expect("fits");
    String::from_utf8(buf[..n].to_vec()).unwrap()
}

#[test]
fn decode_a_frame() {
    let f = decode_frame(
        br#"{"a_lon":-1.5,"a_lat":0.25,"a_mag":1.5,"yaw_rate":-12.75,"speed":7.0,
             "lat_err":0.125,"collisions":{"pedestrian":1,"vehicle":2,"layout":3,"workzone":4}}"#,
    )
    .unwrap();
    assert_eq!(
        f,
        Frame {
            a_lon: -1.5,
            a_lat: 0.25,
            a_mag: 1.5,
            yaw_rate: -12.75,
            speed: 7.0,
            lat_err: Some(0.125),
            collisions: Collisions {
                pedestrian: 1,
                vehicle: 2,
                layout: 3,
                workzone: 4
            },
        }
    );
    // lat_err and collisions (and each count) are optional; integers are accepted as floats.
    let g = decode_frame(br#"{"a_lon":0,"a_lat":0,"a_mag":0,"yaw_rate":0,"speed":0}"#).unwrap();
    assert_eq!(g, Frame::default());
    let h = decode_frame(
        br#"{"a_lon":1,"a_lat":0,"a_mag":1,"yaw_rate":0,"speed":3,"collisions":{"layout":2}}"#,
    )
    .unwrap();
    assert_eq!(h.collisions.layout, 2);
    assert_eq!(h.collisions.total(), 2);
    // A decimal that is not a binary float rounds to the nearest f32, like a Rust literal.
    let d = decode_frame(br#"{"a_lon":0.1,"a_lat":0,"a_mag":0,"yaw_rate":0,"speed":0}"#).unwrap();
    assert_eq!(d.a_lon.to_bits(), 0.1f32.to_bits());
}

#[test]
fn decode_errors() {
    // Missing field, wrong type, not JSON: Syntax.
    for bad in [
        &br#"{"a_lat":0,"a_mag":0,"yaw_rate":0,"speed":0}"#[..],
        br#"{"a_lon":"x","a_lat":0,"a_mag":0,"yaw_rate":0,"speed":0}"#,
        br#"{"a_lon":0,"a_lat":0,"a_mag":0,"yaw_rate":0,"speed":0,"collisions":{"vehicle":-1}}"#,
        br#"{"a_lon":0,"a_lat":0,"a_mag":0,"yaw_rate":0,"speed":0,"collisions":{"vehicle":70000}}"#,
        b"[1,2,3]",
        b"",
        b"{",
    ] {
        assert_eq!(
            decode_frame(bad),
            Err(JsonError::Syntax),
            "{}",
            String::from_utf8_lossy(bad)
        );
    }
    // Valid JSON, invalid frame: the field is named.
    assert_eq!(
        decode_frame(br#"{"a_lon":0,"a_lat":0,"a_mag":0,"yaw_rate":0,"speed":-1}"#),
        Err(JsonError::Frame(FrameError::Negative(Field::Speed)))
    );
    assert_eq!(
        decode_frame(br#"{"a_lon":0,"a_lat":0,"a_mag":-0.5,"yaw_rate":0,"speed":1}"#),
        Err(JsonError::Frame(FrameError::Negative(Field::AMag)))
    );
    // A number beyond f32 is refused, never passed on as infinity.
    let r = decode_frame(br#"{"a_lon":1e39,"a_lat":0,"a_mag":0,"yaw_rate":0,"speed":0}"#);
    assert!(
        matches!(
            r,
            Err(JsonError::Syntax) | Err(JsonError::Frame(FrameError::NonFinite(Field::ALon)))
        ),
        "{r:?}"
    );
}

#[test]
fn encode_events_byte_exact() {
    let collision = Event::Collision(CollisionVerdict {
        frame: 812,
        collisions: Collisions {
            vehicle: 1,
            workzone: 1,
            ..Collisions::NONE
        },
        speed: 6.25,
        decelerated: false,
        exempt: false,
    });
    assert_eq!(
        enc(&collision),
        r#"{"collision":{"frame":812,"collisions":{"pedestrian":0,"vehicle":1,"layout":0,"workzone":1},"speed":6.25,"decelerated":false,"exempt":false}}"#
    );
    let comfort = Event::Comfort(ComfortVerdict {
        chunk: 3,
        frames: 20,
        failed: Failures {
            lon_jerk: true,
            yaw_rate: true,
            ..Failures::default()
        },
    });
    assert_eq!(
        enc(&comfort),
        r#"{"comfort":{"chunk":3,"frames":20,"failed":{"lon_acc":false,"lat_acc":false,"mag_jerk":false,"lon_jerk":true,"yaw_acc":false,"yaw_rate":true}}}"#
    );
    // f32 floats in their shortest round-trip form: 0.3f32 -> "0.3", 1.0 -> "1.0".
    let lateral = Event::Lateral(LateralVerdict {
        chunk: 7,
        max_excess: 0.3,
        band: Band::Anomalous,
    });
    assert_eq!(
        enc(&lateral),
        r#"{"lateral":{"chunk":7,"max_excess":0.3,"band":"anomalous"}}"#
    );
    let critical = Event::Lateral(LateralVerdict {
        chunk: 0,
        max_excess: 1.0,
        band: Band::Critical,
    });
    assert_eq!(
        enc(&critical),
        r#"{"lateral":{"chunk":0,"max_excess":1.0,"band":"critical"}}"#
    );
}

#[test]
fn encode_a_summary_byte_exact() {
    let mut s = RouteSummary {
        frames: 41,
        ..RouteSummary::default()
    };
    s.comfort.chunks = 2;
    s.comfort.comfortable = 1;
    s.comfort.failed.mag_jerk = 1;
    s.lateral.chunks = 3;
    s.lateral.scored_chunks = 2;
    s.lateral.critical = 1;
    s.collisions.aligned = 2;
    s.collisions.exempt = 1;
    s.collisions.nodecel = 1;
    assert_eq!(
        enc(&s),
        concat!(
            r#"{"frames":41,"comfort":{"chunks":2,"comfortable":1,"failed":{"lon_acc":0,"lat_acc":0,"#,
            r#""mag_jerk":1,"lon_jerk":0,"yaw_acc":0,"yaw_rate":0}},"lateral":{"chunks":3,"#,
            r#""scored_chunks":2,"anomalous":0,"critical":1},"collisions":{"aligned":2,"exempt":1,"#,
            r#""nodecel":1}}"#
        )
    );
}

#[test]
fn encode_a_frame_and_decode_it_back() {
    let f = Frame {
        a_lon: -0.1,
        a_lat: 3.0e-5,
        a_mag: 2.5,
        yaw_rate: 57.29578,
        speed: 12.0,
        lat_err: None,
        collisions: Collisions {
            layout: 1,
            ..Collisions::NONE
        },
    };
    // ryu's shortest form: plain decimals down to 1e-5 ("0.00003"), -0.1f32 -> "-0.1".
    let s = enc(&f);
    assert_eq!(
        s,
        r#"{"a_lon":-0.1,"a_lat":0.00003,"a_mag":2.5,"yaw_rate":57.29578,"speed":12.0,"lat_err":null,"collisions":{"pedestrian":0,"vehicle":0,"layout":1,"workzone":0}}"#
    );
    assert_eq!(decode_frame(s.as_bytes()), Ok(f));
}

#[test]
fn a_small_buffer_is_an_error() {
    let mut buf = [0u8; 10];
    assert_eq!(
        encode(&RouteSummary::default(), &mut buf),
        Err(JsonError::BufferFull)
    );
    // The JSON of the default summary is 223 bytes: 222 is too small, 223 fits.
    let n = enc(&RouteSummary::default()).len();
    let mut exact = vec![0u8; n];
    assert_eq!(encode(&RouteSummary::default(), &mut exact), Ok(n));
    let mut short = vec![0u8; n - 1];
    assert_eq!(
        encode(&RouteSummary::default(), &mut short),
        Err(JsonError::BufferFull)
    );
}
