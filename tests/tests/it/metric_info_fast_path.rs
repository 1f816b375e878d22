//! The two `metric_info.json` parse paths agree: the fast path (a strict scanner) never accepts
//! what the serde_json visitor rejects, and never reads a value differently.
//!
//! For every input (the fuzz corpus, hand-picked edge cases, generated files with numbers of
//! every shape and keys in every order, mutated files, arbitrary bytes):
//! - if the fast path returns frames, the serde path accepts the input too, with the same
//!   frames: same steps in the same order, the same gap count, and every f64 / f32 equal bit for
//!   bit (`-0.0` is not `0.0` here);
//! - `parse_metric_info` (fast path first, serde on any doubt) gives exactly what
//!   `parse_metric_info_serde` gives: the same frames bit for bit, or the same error (variant and
//!   message).
//!
//! The fast path must also actually be taken on well-formed files (else the test proves
//! nothing): that is asserted where the inputs are well-formed.

use std::path::Path;

use monitor_host::input::metric_info::{
    parse_metric_info, parse_metric_info_fast, parse_metric_info_serde, Telemetry, TelemetryError,
};
use proptest::prelude::*;
use proptest::test_runner::Config as PropConfig;

/// Every number of a telemetry as raw bits, with the steps and the gap count.
fn bits(t: &Telemetry) -> (u64, Vec<[u64; 10]>) {
    let frames = t
        .frames
        .iter()
        .map(|f| {
            [
                f.step,
                f.location[0].to_bits(),
                f.location[1].to_bits(),
                u64::from(f.acc[0].to_bits()),
                u64::from(f.acc[1].to_bits()),
                u64::from(f.fwd[0].to_bits()),
                u64::from(f.fwd[1].to_bits()),
                u64::from(f.right[0].to_bits()),
                u64::from(f.right[1].to_bits()),
                u64::from(f.yaw_rate_deg.to_bits()),
            ]
        })
        .collect();
    (t.gaps, frames)
}

fn show(bytes: &[u8]) -> String {
    String::from_utf8_lossy(&bytes[..bytes.len().min(4000)]).into_owned()
}

/// Checks one input; returns whether the fast path took it.
fn check(bytes: &[u8]) -> bool {
    let serde = parse_metric_info_serde(bytes);
    let fast = parse_metric_info_fast(bytes);
    if let Some(f) = &fast {
        match &serde {
            Ok(s) => assert_eq!(bits(f), bits(s), "values differ on {:?}", show(bytes)),
            Err(e) => panic!(
                "fast path accepted what serde_json rejects ({e}): {:?}",
                show(bytes)
            ),
        }
    }
    match (parse_metric_info(bytes), &serde) {
        (Ok(a), Ok(b)) => assert_eq!(bits(&a), bits(b), "{:?}", show(bytes)),
        (Err(a), Err(b)) => {
            assert_eq!(a.to_string(), b.to_string(), "{:?}", show(bytes));
            assert_eq!(
                std::mem::discriminant(&a),
                std::mem::discriminant::<TelemetryError>(b)
            );
        }
        (a, b) => panic!("paths disagree: {a:?} vs {b:?} on {:?}", show(bytes)),
    }
    fast.is_some()
}

// ---------------------------------------------------------------------------------------------
// Files of our making.

const FIELDS: [&str; 5] = [
    "acceleration",
    "angular_velocity",
    "forward_vector",
    "right_vector",
    "location",
];

/// A JSON number of any shape serde_json accepts (and a few it does not).
fn number() -> impl Strategy<Value = String> {
    prop_oneof![
        // Python's repr of widened CARLA float32 values and of doubles.
        4 => any::<f32>().prop_filter("finite", |x| x.is_finite())
            .prop_map(|x| format!("{:?}", f64::from(x))),
        3 => any::<f64>().prop_filter("finite", |x| x.is_finite()).prop_map(|x| format!("{x:?}")),
        2 => (-1e4f64..1e4).prop_map(|x| format!("{x}")),
        2 => any::<i64>().prop_map(|n| n.to_string()),
        1 => any::<u64>().prop_map(|n| n.to_string()),
        // Integers beyond u64 / i64, long mantissas, exponents of every form.
        1 => "-?[1-9][0-9]{18,30}",
        1 => "-?[0-9]\\.[0-9]{17,40}",
        1 => "-?[1-9][0-9]{0,3}(\\.[0-9]{1,20})?[eE][-+]?[0-9]{1,3}",
        1 => proptest::sample::select(vec![
            "0", "-0", "0.0", "-0.0", "-0e0", "0e-5", "-0.0e+3", "1e-400", "-1e-400", "1e400",
            "4.9e-324", "2.4703282292062327e-324", "2.4703282292062328e-324",
            "1.7976931348623157e308", "1.7976931348623158e308", "1.7976931348623159e308",
            "3.4028235e38", "3.4028236e38", "3.40282357e38", "1e39", "-1e39",
            "9007199254740993", "18446744073709551615", "18446744073709551616",
            "-9223372036854775808", "-9223372036854775809",
            "0.1000000000000000055511151231257827021181583404541015625",
            "01", "1.", ".5", "+1", "1e", "-", "--1", "1e+", "NaN", "Infinity", "-Infinity",
            "1E2", "1e02", "00", "-01", "0.0e", "1.5E-0",
        ]).prop_map(String::from),
    ]
}

/// A JSON value for an ignored key: scalars, strings with escapes, nested containers.
fn ignored_value() -> impl Strategy<Value = String> {
    let leaf = prop_oneof![
        number(),
        Just("null".to_string()),
        Just("true".to_string()),
        Just("false".to_string()),
        proptest::sample::select(vec![
            r#""""#,
            r#""text""#,
            r#""\u0041\n\t\"\\\/""#,
            r#""\ud83d\ude00""#,
            r#""\ud800""#,
            r#""\udc00x""#,
            "\"caf\u{e9}\"",
            r#""\u0000""#,
            r#""\x""#,
            "\"tab\there\"",
        ])
        .prop_map(String::from),
    ];
    leaf.prop_recursive(6, 24, 4, |inner| {
        prop_oneof![
            proptest::collection::vec(inner.clone(), 0..4)
                .prop_map(|v| format!("[{}]", v.join(","))),
            proptest::collection::vec(("[a-z]{0,3}", inner), 0..3).prop_map(|v| {
                let parts: Vec<String> = v.iter().map(|(k, x)| format!("\"{k}\": {x}")).collect();
                format!("{{{}}}", parts.join(", "))
            }),
        ]
    })
}

/// Whitespace between tokens: mostly what Python writes, sometimes every JSON whitespace byte.
fn ws() -> impl Strategy<Value = String> {
    prop_oneof![
        6 => Just(" ".to_string()),
        3 => Just("\n        ".to_string()),
        2 => Just(String::new()),
        1 => "[ \t\r\n]{0,3}",
    ]
}

/// One frame: the five vectors (sometimes repeated, dropped, short or long, not numbers) and
/// ignored keys, in any order.
fn frame() -> impl Strategy<Value = String> {
    let vector =
        (proptest::collection::vec(number(), 3..5), 0u8..20).prop_map(|(nums, odd)| match odd {
            0 => format!("[{}]", nums[..2].join(", ")),
            1 => "[1.0, \"2\", 3.0]".to_string(),
            2 => "{\"x\": 1}".to_string(),
            3 => "[[1.0], 2.0, 3.0]".to_string(),
            4 => "null".to_string(),
            _ => format!("[{}]", nums.join(", ")),
        });
    let required = proptest::collection::vec(vector, 5);
    let ignored = proptest::collection::vec(
        (
            proptest::sample::select(vec![
                "rotation",
                "velocity",
                "speed",
                "x",
                "",
                "Location",
                "location ",
                "\\u0061cceleration",
                "acceleration",
                "right_vector",
            ]),
            ignored_value(),
        ),
        0..3,
    );
    (required, ignored, any::<u64>(), ws(), 0u8..12).prop_map(|(req, ign, order, w, drop)| {
        let mut parts: Vec<String> = FIELDS
            .iter()
            .zip(&req)
            .enumerate()
            .filter(|(i, _)| usize::from(drop) != *i)
            .map(|(_, (k, v))| format!("\"{k}\":{w}{v}"))
            .collect();
        parts.extend(ign.iter().map(|(k, v)| format!("\"{k}\":{w}{v}")));
        // A deterministic shuffle from `order`.
        let n = parts.len();
        for i in (1..n).rev() {
            let j = (order.rotate_left(i as u32) % (i as u64 + 1)) as usize;
            parts.swap(i, j);
        }
        format!("{{{w}{}{w}}}", parts.join(&format!(",{w}")))
    })
}

/// A step key: mostly plain, sometimes with leading zeros, escapes or not decimal at all.
fn step_key(i: usize) -> impl Strategy<Value = String> {
    prop_oneof![
        12 => Just((i + 1).to_string()),
        1 => Just(format!("00{}", i + 1)),
        1 => Just(format!("\\u003{}", (i + 1) % 10)),
        1 => proptest::sample::select(vec![
            "1", "x", "", "-1", "1.0", "18446744073709551615", "18446744073709551616",
        ]).prop_map(String::from),
    ]
}

/// A whole file of 1..6 frames.
fn file() -> impl Strategy<Value = String> {
    (1usize..6).prop_flat_map(|n| {
        let frames: Vec<_> = (0..n).map(|i| (step_key(i), frame())).collect();
        (frames, ws(), any::<bool>()).prop_map(|(frames, w, rev)| {
            let mut parts: Vec<String> = frames
                .iter()
                .map(|(k, f)| format!("\"{k}\":{w}{f}"))
                .collect();
            if rev {
                parts.reverse();
            }
            format!("{{{w}{}{w}}}", parts.join(&format!(",{w}")))
        })
    })
}

/// A well-formed file in Python's `json.dump(indent=4)` layout.
fn healthy(frames: &[[String; 5]]) -> String {
    let body: Vec<String> = frames
        .iter()
        .enumerate()
        .map(|(i, v)| {
            let fields: Vec<String> = FIELDS
                .iter()
                .zip(v)
                .map(|(k, x)| format!("        \"{k}\": {x}"))
                .chain(std::iter::once(
                    "        \"rotation\": [\n            0.0,\n            1.5,\n            -90.0\n        ]"
                        .to_string(),
                ))
                .collect();
            format!("    \"{}\": {{\n{}\n    }}", i + 1, fields.join(",\n"))
        })
        .collect();
    format!("{{\n{}\n}}", body.join(",\n"))
}

fn healthy_strategy() -> impl Strategy<Value = String> {
    let vec3 = proptest::collection::vec(number(), 3)
        .prop_map(|v| format!("[\n            {}\n        ]", v.join(",\n            ")));
    proptest::collection::vec(proptest::collection::vec(vec3, 5), 1..5).prop_map(|fs| {
        let frames: Vec<[String; 5]> = fs
            .into_iter()
            .map(|v| v.try_into().expect("five vectors"))
            .collect();
        healthy(&frames)
    })
}

/// A byte that matters to a JSON parser.
fn nasty_byte() -> impl Strategy<Value = u8> {
    prop_oneof![
        proptest::sample::select(
            b"{}[]:,\"\\ \t\r\n0123456789-+.eEnulftrI\x00\x01\x1f\x7f\x80\xbf\xc3\xe2\xf0\xff"
                .to_vec()
        ),
        any::<u8>(),
    ]
}

#[derive(Clone, Debug)]
enum Mutation {
    Set(usize, u8),
    Insert(usize, u8),
    Delete(usize),
    InsertText(usize, &'static str),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        3 => (any::<usize>(), nasty_byte()).prop_map(|(i, b)| Mutation::Set(i, b)),
        2 => (any::<usize>(), nasty_byte()).prop_map(|(i, b)| Mutation::Insert(i, b)),
        2 => any::<usize>().prop_map(Mutation::Delete),
        2 => (
            any::<usize>(),
            proptest::sample::select(vec![
                "-0", "-0,", "1e999", "NaN", "\\u0000", "\\ud800", "\"", "[", "]", "{", "}",
                ",", ":", "\"x\":", "\u{feff}", "\u{a0}", "\x0b", "00", ".", "e+",
            ])
        )
            .prop_map(|(i, t)| Mutation::InsertText(i, t)),
    ]
}

fn mutate(mut bytes: Vec<u8>, ms: &[Mutation]) -> Vec<u8> {
    for m in ms {
        let n = bytes.len();
        match *m {
            Mutation::Set(i, b) if n > 0 => bytes[i % n] = b,
            Mutation::Insert(i, b) => bytes.insert(i % (n + 1), b),
            Mutation::Delete(i) if n > 0 => {
                bytes.remove(i % n);
            }
            Mutation::InsertText(i, t) => {
                let at = i % (n + 1);
                bytes.splice(at..at, t.bytes());
            }
            _ => {}
        }
    }
    bytes
}

/// Cases per property: 1,000 on every run; `SDS_FAST_PATH_CASES` for a longer soak.
fn cases() -> PropConfig {
    let n = std::env::var("SDS_FAST_PATH_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(1000);
    PropConfig::with_cases(n)
}

proptest! {
    #![proptest_config(cases())]

    #[test]
    fn generated_files_agree(text in file()) {
        check(text.as_bytes());
    }

    #[test]
    fn healthy_files_agree_and_take_the_fast_path(text in healthy_strategy()) {
        let serde_ok = parse_metric_info_serde(text.as_bytes()).is_ok();
        let fast = check(text.as_bytes());
        // Bench2Drive's layout, valid: the fast path must take it, whatever the numbers' shape.
        if serde_ok {
            prop_assert!(fast, "fast path refused a valid file: {}", text);
        }
    }

    #[test]
    fn mutated_files_agree(
        text in healthy_strategy(),
        ms in proptest::collection::vec(mutation(), 1..4),
    ) {
        check(&mutate(text.into_bytes(), &ms));
    }

    #[test]
    fn arbitrary_bytes_agree(bytes in proptest::collection::vec(any::<u8>(), 0..200)) {
        check(&bytes);
    }
}

// ---------------------------------------------------------------------------------------------
// Fixed inputs.

/// One valid frame with `loc` as the location's x, and `extra` appended inside the frame.
fn one_frame(loc: &str, extra: &str) -> String {
    format!(
        r#"{{"1": {{"acceleration": [0.5, 0.25, 0], "angular_velocity": [0, 0, 3],
        "forward_vector": [1, 0, 0], "right_vector": [0, 1, 0], "location": [{loc}, 2, 0]{extra}}}}}"#
    )
}

#[test]
fn edge_cases_agree() {
    let nested = |d: usize| format!(", \"deep\": {}1{}", "[".repeat(d), "]".repeat(d));
    let mut cases: Vec<Vec<u8>> = vec![
        one_frame("1.5", ""),
        one_frame("-0", ""),
        one_frame("-0.0", ""),
        one_frame("0", ""),
        one_frame("1e999", ""),
        one_frame("1.5", ", \"rotation\": [1e999]"),
        one_frame("1.5", ", \"rotation\": [NaN]"),
        one_frame("18446744073709551616", ""),
        one_frame("-9223372036854775809", ""),
        one_frame("123456789012345678901234567890", ""),
        one_frame("1.5", ", \"s\": \"\\ud800\""),
        one_frame("1.5", ", \"s\": \"\\udc00\""),
        one_frame("1.5", ", \"\\ud800\": 1"),
        one_frame("1.5", ", \"s\": \"a\tb\""),
        one_frame("1.5", ", \"s\": \"\u{7f}\""),
        one_frame("1.5", ", \"location\": [1, 2, 3]"),
        one_frame("1.5", ", \"rotation\": 1, \"rotation\": 2"),
        one_frame("1.5", &nested(20)),
        one_frame("1.5", &nested(40)),
        one_frame("1.5", &nested(126)),
        one_frame("1.5", &nested(127)),
        one_frame("1.5", &nested(128)),
        one_frame("1.5", &nested(5000)),
        format!("{} x", one_frame("1.5", "")),
        format!("{}}}", one_frame("1.5", "")),
        format!("\u{feff}{}", one_frame("1.5", "")),
        format!("{}\u{a0}", one_frame("1.5", "")),
        format!("{}\x0c", one_frame("1.5", "")),
        format!("{}\0", one_frame("1.5", "")),
        one_frame("1.5", "").replace("\"1\"", "\"\\u0031\""),
        one_frame("1.5", "").replace("\"1\"", "\"01\""),
        one_frame("1.5", "").replace("\"location\"", "\"\\u006cocation\""),
        "{}".into(),
        "{".into(),
        "".into(),
        "[]".into(),
        " {\"1\": {}} ".into(),
    ]
    .into_iter()
    .map(String::into_bytes)
    .collect();
    // Long mantissas at every early position (simd-json 0.15 misreads these, see
    // docs/PERFORMANCE.md: a fast path must not), and junk right after a long float.
    for digits in [19, 20, 25, 40, 4000, 4031, 4032, 4039, 4040, 4100] {
        for lead in 0..70 {
            let x = format!("1.{}E005", "6".repeat(digits));
            let text = one_frame(&x, "");
            let pad = " ".repeat(lead);
            cases.push(format!("{pad}{text}").into_bytes());
            let y = format!("0.{}{}", "0".repeat(digits / 2), "7".repeat(digits / 2));
            cases.push(format!("{pad}{}", one_frame(&y, "")).into_bytes());
        }
    }
    for junk in ["x", ".5", "-5", "\u{7f}", "e", "\0"] {
        let x = format!("-3.25110033215773315463{junk}70830533583");
        cases.push(one_frame(&x, "").into_bytes());
    }
    cases.push(b"{\"1\": {\"s\": \"\xff\"}}".to_vec());
    cases.push(b"{\"1\xc3\": {}}".to_vec());
    let taken = cases.iter().filter(|c| check(c)).count();
    assert!(taken >= 500, "the fast path took only {taken} edge cases");
}

#[test]
fn fuzz_corpus_agrees() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fuzz/corpus/metric_info");
    let mut n = 0;
    let mut taken = 0;
    for entry in std::fs::read_dir(&dir).expect("the fuzz corpus is in the repository") {
        let path = entry.expect("entry").path();
        let bytes = std::fs::read(&path).expect("readable");
        n += 1;
        let fast = check(&bytes);
        taken += usize::from(fast);
        if !fast && parse_metric_info_serde(&bytes).is_ok() {
            eprintln!("valid, left to serde: {}", path.display());
        }
    }
    assert!(n > 100, "only {n} corpus files in {}", dir.display());
    // Most corpus files are invalid; the valid ones the fast path leaves have a required
    // vector of more than three numbers (legal, never written by Bench2Drive).
    assert!(
        taken >= 5,
        "the fast path took only {taken} of {n} corpus files"
    );
    eprintln!("fuzz corpus: {n} files, {taken} through the fast path");
}

#[test]
fn benchmark_layouts_take_the_fast_path() {
    use monitor_host::demo::{write_large_with, LargeLayout};
    for layout in [LargeLayout::Bench2Drive, LargeLayout::Wide] {
        let dir = tempfile::tempdir().expect("temp dir");
        let run = write_large_with(dir.path(), 2, 300, layout, 0).expect("written");
        for entry in walk(&run.telemetry) {
            let bytes = std::fs::read(&entry).expect("readable");
            assert!(check(&bytes), "{layout:?}: {} not fast", entry.display());
        }
    }
}

fn walk(dir: &Path) -> Vec<std::path::PathBuf> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).expect("dir") {
        let p = e.expect("entry").path();
        if p.is_dir() {
            out.extend(walk(&p));
        } else if p.file_name().is_some_and(|n| n == "metric_info.json") {
            out.push(p);
        }
    }
    out
}
