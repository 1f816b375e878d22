//! The live link (docs/SCORE.md, "Live link"): the checker never turns a link fault into a wrong
//! verdict.
//!
//! Random routes go through the doer's encoding and a random fault plan (drop, corrupt any
//! bytes, duplicate, reorder, stall, garbage between messages) into a `Checker`, message by
//! message on a virtual clock. Then:
//! - a frame is accepted only while its own message's bytes are fed, and only if they arrived
//!   unmodified: no corrupted message is ever accepted;
//! - a new segment starts exactly at the route's first accepted frame and at the first one after
//!   a `WRONGSEQUENCE` or `NONEWDATA`;
//! - the checker's monitor events and summary equal the replay of the frames it accepted, cut
//!   into its segments (a fresh `Monitor` per segment; events compared field by field);
//! - every single-byte corruption and every burst of up to 32 bits of a message is caught.
//!
//! Cases: `PROPTEST_CASES` if set, else 2,000. Run:
//! `cargo test -p sds-tests --release --test it link_checker::`.

use monitor_core::link::{
    self, e2e, CheckStatus, Checker, Deframer, LinkConfig, LinkEvent, LinkSummary, Message, Tagged,
};
use monitor_core::{Bounds, Collisions, Config, Event, Frame, Monitor, Profile};
use proptest::collection::vec;
use proptest::prelude::*;
use proptest::test_runner::Config as ProptestConfig;

fn cases(default: u32) -> u32 {
    std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(default)
}

fn frame() -> impl Strategy<Value = Frame> {
    (
        (
            -6.0f32..4.0,
            -5.0f32..5.0,
            0.0f32..7.0,
            -60.0f32..60.0,
            0.0f32..25.0,
        ),
        prop::option::weighted(0.8, 0.0f32..2.0),
        prop::option::weighted(0.03, (0u16..2, 0u16..2, 0u16..2, 0u16..2)),
    )
        .prop_map(
            |((a_lon, a_lat, a_mag, yaw_rate, speed), lat_err, c)| Frame {
                a_lon,
                a_lat,
                a_mag,
                yaw_rate,
                speed,
                lat_err,
                collisions: c
                    .map(|(p, v, l, w)| Collisions {
                        pedestrian: p,
                        vehicle: v,
                        layout: l,
                        workzone: w,
                    })
                    .unwrap_or_default(),
            },
        )
}

/// What happens to one frame message on the way.
#[derive(Clone, Debug)]
enum Fault {
    Pass,
    Drop,
    /// XOR these (position seed, nonzero value) pairs into the encoded bytes.
    Corrupt(Vec<(usize, u8)>),
    Duplicate,
    /// Swap with the next message.
    Reorder,
    /// The cable pulled for this many frame periods before the message.
    Stall(u8),
    /// Random bytes before the message.
    Garbage(Vec<u8>),
}

fn fault() -> impl Strategy<Value = Fault> {
    prop_oneof![
        40 => Just(Fault::Pass),
        2 => Just(Fault::Drop),
        2 => vec((any::<usize>(), 1u8..=255), 1..4).prop_map(Fault::Corrupt),
        1 => Just(Fault::Duplicate),
        1 => Just(Fault::Reorder),
        1 => (1u8..8).prop_map(Fault::Stall),
        1 => vec(any::<u8>(), 1..20).prop_map(Fault::Garbage),
    ]
}

fn config() -> impl Strategy<Value = Config> {
    (prop::sample::select(Profile::ALL.to_vec()), 7u16..=20).prop_map(|(profile, chunk_len)| {
        Config {
            profile,
            chunk_len,
            // Each profile's own bounds (Autoware's with the physical ones is refused).
            bounds: Bounds::of(profile),
            ..Config::DEFAULT
        }
    })
}

/// One piece of the stream: bytes fed at once, and the frame if they are one intact message.
struct Chunk {
    bytes: Vec<u8>,
    intact: Option<(u16, Frame)>,
    stall: u8,
}

fn encoded(m: &Message, counter: u16) -> Vec<u8> {
    let mut buf = [0u8; link::MAX_ENCODED];
    let n = link::encode(m, counter, &mut buf);
    buf[..n].to_vec()
}

fn chunks(frames: &[Frame], first: u16, plan: &[Fault]) -> Vec<Chunk> {
    let mut out: Vec<Chunk> = Vec::new();
    for (i, (f, fault)) in frames.iter().zip(plan).enumerate() {
        let counter = first.wrapping_add(i as u16);
        let mut bytes = encoded(&Message::Frame(*f), counter);
        let intact = Some((counter, *f));
        let chunk = |bytes, intact, stall| Chunk {
            bytes,
            intact,
            stall,
        };
        match fault {
            Fault::Pass => out.push(chunk(bytes, intact, 0)),
            Fault::Drop => {}
            Fault::Corrupt(hits) => {
                let mut done = std::collections::BTreeSet::new();
                for (pos, x) in hits {
                    let p = pos % bytes.len();
                    if done.insert(p) {
                        bytes[p] ^= x;
                    }
                }
                out.push(chunk(bytes, None, 0));
            }
            Fault::Duplicate => {
                out.push(chunk(bytes.clone(), intact, 0));
                out.push(chunk(bytes, intact, 0));
            }
            Fault::Reorder => {
                out.push(chunk(bytes, intact, 0));
                // Swapped with the one before it, when there is one.
                let n = out.len();
                if n >= 2 {
                    out.swap(n - 1, n - 2);
                }
            }
            Fault::Stall(p) => out.push(chunk(bytes, intact, *p)),
            Fault::Garbage(g) => {
                out.push(chunk(g.clone(), None, 0));
                out.push(chunk(bytes, intact, 0));
            }
        }
    }
    out
}

/// Decodes the checker's answers.
fn answers(rx: &mut Deframer, bytes: &[u8]) -> Vec<Message> {
    let mut got = Vec::new();
    for &b in bytes {
        if let Some(Ok(m)) = rx.push(b) {
            let (_, msg) = link::decode(m).expect("the checker's own message decodes");
            got.push(msg);
        }
    }
    got
}

/// The replay: a fresh monitor per segment, events tagged with the frame's counter (a
/// segment's last events with its last frame's).
fn replay(config: Config, segments: &[Vec<(u16, Frame)>]) -> (Vec<Tagged>, LinkSummary) {
    let mut events = Vec::new();
    let mut summary = LinkSummary::default();
    for seg in segments {
        let mut m: Monitor = Monitor::new(config).unwrap();
        for w in seg.windows(2) {
            summary.gaps += u32::from(w[1].0.wrapping_sub(w[0].0)) - 1;
        }
        for (c, f) in seg {
            for e in &m.push(f).unwrap() {
                events.push(Tagged {
                    counter: *c,
                    event: LinkEvent::Monitor(*e),
                });
            }
        }
        let done = m.finish().unwrap();
        let last = seg.last().unwrap().0;
        for e in &done.events {
            events.push(Tagged {
                counter: last,
                event: LinkEvent::Monitor(*e),
            });
        }
        summary.add_segment(&done.summary);
    }
    (events, summary)
}

const DT_US: u64 = 50_000;

/// Plays one route into `checker` and checks every property.
#[allow(clippy::too_many_arguments)]
fn play_route(
    checker: &mut Checker,
    start_counter: u16,
    config: Config,
    frames: &[Frame],
    first: u16,
    plan: &[Fault],
    clock: &mut u64,
    fresh: bool,
) -> Result<(), TestCaseError> {
    let mut rx = Deframer::new();
    let mut out = Vec::new();
    let start = encoded(&Message::Start(config), start_counter);
    checker.receive(&start, *clock, &mut |b: &[u8]| out.extend_from_slice(b));
    let got = answers(&mut rx, &out);
    prop_assert!(
        matches!(got.last(), Some(Message::Status(_))),
        "a start is answered"
    );

    let mut accepted: Vec<(u16, Frame)> = Vec::new();
    let mut segments: Vec<Vec<(u16, Frame)>> = Vec::new();
    let mut events: Vec<Tagged> = Vec::new();
    let mut cut_pending = false;
    for chunk in chunks(frames, first, plan) {
        out.clear();
        let before = checker.status();
        for _ in 0..chunk.stall {
            *clock += DT_US;
            checker.poll(*clock, &mut |b: &[u8]| out.extend_from_slice(b));
        }
        *clock += DT_US;
        checker.poll(*clock, &mut |b: &[u8]| out.extend_from_slice(b));
        checker.receive(&chunk.bytes, *clock, &mut |b: &[u8]| {
            out.extend_from_slice(b)
        });
        let after = checker.status();
        // Statuses up to this chunk's message: a cut since the last accepted frame?
        let cuts = |s: &link::Status| {
            s.counts.get(CheckStatus::WrongSequence) + s.counts.get(CheckStatus::NoNewData)
        };
        let new_cut = cuts(&after) > cuts(&before);
        let mut segment_here = false;
        for m in answers(&mut rx, &out) {
            if let Message::Event(t) = m {
                match t.event {
                    LinkEvent::Segment { index } => {
                        prop_assert_eq!(index as usize, segments.len());
                        segment_here = true;
                    }
                    LinkEvent::Monitor(_) => events.push(t),
                    LinkEvent::LinkFault { .. } | LinkEvent::LinkRestored { .. } => {}
                }
            }
        }
        match after.accepted - before.accepted {
            0 => {
                prop_assert!(!segment_here, "a segment starts only at an accepted frame");
                cut_pending |= new_cut;
            }
            1 => {
                let Some((c, f)) = chunk.intact else {
                    return Err(TestCaseError::fail("a corrupted message was accepted"));
                };
                // The statuses counted in this chunk before its frame (a poll's NONEWDATA) cut
                // too; the frame's own status is OK or OKSOMELOST.
                let expect_cut = accepted.is_empty() || cut_pending || new_cut;
                prop_assert_eq!(segment_here, expect_cut, "segment at counter {}", c);
                if segment_here {
                    segments.push(Vec::new());
                }
                segments.last_mut().unwrap().push((c, f));
                accepted.push((c, f));
                cut_pending = false;
            }
            n => return Err(TestCaseError::fail(format!("{n} frames accepted at once"))),
        }
    }
    // The end, repeated until answered (a corrupted last delimiter swallows the first copy).
    let end = encoded(
        &Message::End {
            frames: frames.len() as u32,
        },
        start_counter,
    );
    let mut summary = None;
    for _ in 0..2 {
        out.clear();
        checker.receive(&end, *clock, &mut |b: &[u8]| out.extend_from_slice(b));
        for m in answers(&mut rx, &out) {
            match m {
                Message::Event(t) if matches!(t.event, LinkEvent::Monitor(_)) => events.push(t),
                Message::Summary(s) => summary = Some(s),
                _ => {}
            }
        }
        if summary.is_some() {
            break;
        }
    }
    let summary = summary.expect("an end is answered with the summary");
    let (want_events, want) = replay(config, &segments);
    prop_assert_eq!(&events, &want_events);
    prop_assert_eq!(summary.route, want.route);
    prop_assert_eq!(summary.segments, want.segments);
    prop_assert_eq!(summary.gaps, want.gaps);
    prop_assert_eq!(
        summary.counts.get(CheckStatus::Ok) + summary.counts.get(CheckStatus::OkSomeLost),
        accepted.len() as u32
    );
    // Without faults on a fresh checker: the whole route in one segment. (After a route whose
    // last frames were lost, the next route's first frame may be a WRONGSEQUENCE: counters
    // run on across routes.)
    if fresh && plan.iter().all(|f| matches!(f, Fault::Pass)) {
        prop_assert_eq!(accepted.len(), frames.len());
        prop_assert_eq!(summary.segments, u32::from(!frames.is_empty()));
    }
    Ok(())
}

type Route = (Config, Vec<(Frame, Fault)>);

fn route() -> impl Strategy<Value = Route> {
    (config(), vec((frame(), fault()), 0..160))
}

fn clean_route() -> impl Strategy<Value = Route> {
    (config(), vec((frame(), Just(Fault::Pass)), 0..160))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(2_000), ..ProptestConfig::default() })]

    /// One or two routes on one checker (counters run on across routes), with random faults.
    #[test]
    fn checker_equals_replay_of_accepted_frames(
        routes in vec(prop_oneof![3 => route(), 1 => clean_route()], 1..3),
        first in any::<u16>(),
        start in any::<u16>(),
    ) {
        let mut checker: Checker = Checker::new(LinkConfig::DEFAULT).unwrap();
        let mut clock = 1_000_000;
        let mut counter = first;
        for (i, (config, items)) in routes.iter().enumerate() {
            let (frames, plan): (Vec<Frame>, Vec<Fault>) = items.iter().cloned().unzip();
            play_route(&mut checker, start.wrapping_add(i as u16), *config, &frames, counter,
                       &plan, &mut clock, i == 0)?;
            counter = counter.wrapping_add(frames.len() as u16);
        }
    }

    /// Any message with any burst of up to 32 bits flipped (first and last bit of the burst
    /// set) fails its check.
    #[test]
    fn every_burst_up_to_32_bits_is_caught(
        f in frame(),
        kind in 0usize..4,
        counter in any::<u16>(),
        len in 1usize..=32,
        start_bit in any::<usize>(),
        pattern in any::<u32>(),
    ) {
        let m = match kind {
            0 => Message::Frame(f),
            1 => Message::Start(Config::DEFAULT),
            2 => Message::End { frames: counter.into() },
            _ => Message::Status(Checker::<20>::new(LinkConfig::DEFAULT).unwrap().status()),
        };
        let mut buf = [0u8; link::MAX_MESSAGE];
        let n = link::seal(&m, counter, &mut buf);
        let bits = n * 8;
        let len = len.min(bits);
        let start = start_bit % (bits - len + 1);
        let mut burst = if len == 32 { pattern } else { pattern & ((1u32 << len) - 1) };
        burst |= 1 | (1u32 << (len - 1));
        let mut bad = buf[..n].to_vec();
        for i in 0..len {
            if burst >> i & 1 == 1 {
                let b = start + i;
                bad[b / 8] ^= 0x80 >> (b % 8);
            }
        }
        prop_assert!(link::decode(&bad).is_err());
        prop_assert!(e2e::check(&bad).is_err());
    }

    /// The checker's streaming COBS decoder (`Deframer`) gives what the `cobs` crate's decoder
    /// gives, message by message, on valid encodings, on random bytes and on their mixtures.
    #[test]
    fn streaming_cobs_decode_equals_the_crate(
        pieces in vec(prop_oneof![
            vec(any::<u8>(), 0..300).prop_map(|m| {
                let mut out = vec![0u8; m.len() + m.len() / 254 + 2];
                let n = link::framing::frame(&m, &mut out).unwrap();
                out.truncate(n);
                out
            }),
            vec(any::<u8>(), 0..300),
        ], 1..8),
    ) {
        let stream: Vec<u8> = pieces.concat();
        let mut rx = Deframer::new();
        let mut got = Vec::new();
        for &b in &stream {
            if let Some(r) = rx.push(b) {
                got.push(r.map(|m| m.to_vec()));
            }
        }
        let mut want = Vec::new();
        let mut segments: Vec<&[u8]> = stream.split(|&b| b == 0).collect();
        segments.pop(); // the bytes after the last delimiter: no message yet
        for seg in segments.into_iter().filter(|s| !s.is_empty()) {
            if seg.len() > link::MAX_ENCODED {
                want.push(Err(link::FramingError::TooLong));
                continue;
            }
            let mut copy = seg.to_vec();
            want.push(match cobs::decode_in_place(&mut copy) {
                Ok(n) => Ok(copy[..n].to_vec()),
                Err(_) => Err(link::FramingError::Cobs),
            });
        }
        prop_assert_eq!(got, want);
    }

    /// A stream of random bytes: no panic, nothing accepted, bounded answers.
    #[test]
    fn random_bytes_are_never_accepted(noise in vec(any::<u8>(), 0..4096)) {
        let mut checker: Checker = Checker::new(LinkConfig::DEFAULT).unwrap();
        let mut out = 0usize;
        let start = encoded(&Message::Start(Config::DEFAULT), 0);
        checker.receive(&start, 0, &mut |b: &[u8]| out += b.len());
        checker.receive(&noise, 1, &mut |b: &[u8]| out += b.len());
        checker.poll(10_000_000, &mut |b: &[u8]| out += b.len());
        prop_assert_eq!(checker.status().accepted, 0);
    }
}

/// Every single-byte corruption (each position, each of the 255 changes) of each message kind
/// is caught.
#[test]
fn every_single_byte_corruption_is_caught() {
    let f = Frame {
        a_lon: -1.5,
        speed: 8.0,
        lat_err: Some(0.5),
        ..Frame::default()
    };
    let status = Checker::<20>::new(LinkConfig::DEFAULT).unwrap().status();
    let messages = [
        Message::Frame(f),
        Message::Start(Config::DEFAULT),
        Message::End { frames: 7 },
        Message::Status(status),
        Message::Summary(LinkSummary::default()),
        Message::Event(Tagged {
            counter: 3,
            event: LinkEvent::Segment { index: 1 },
        }),
    ];
    let mut tried = 0;
    for m in &messages {
        let mut buf = [0u8; link::MAX_MESSAGE];
        let n = link::seal(m, 0x1234, &mut buf);
        assert_eq!(link::decode(&buf[..n]).unwrap().1, *m);
        for pos in 0..n {
            for x in 1..=255u8 {
                let mut bad = buf[..n].to_vec();
                bad[pos] ^= x;
                assert!(link::decode(&bad).is_err(), "{m:?}: byte {pos} ^ {x:#04x}");
                tried += 1;
            }
        }
    }
    assert!(tried > 255 * 45 * 6);
}

/// The window: `link_fault` when a third bad status lands in the last 20, `link_restored` when
/// the window holds two again; the pin state follows.
#[test]
fn window_enters_and_leaves_invalid() {
    let mut checker: Checker = Checker::new(LinkConfig::DEFAULT).unwrap();
    let mut out = Vec::new();
    let mut sink = |b: &[u8]| out.extend_from_slice(b);
    checker.receive(&encoded(&Message::Start(Config::DEFAULT), 0), 0, &mut sink);
    let f = Frame::default();
    let mut t = 0;
    let mut send = |checker: &mut Checker, c: u16, sink: &mut dyn FnMut(&[u8])| {
        t += DT_US;
        checker.receive(&encoded(&Message::Frame(f), c), t, &mut |b: &[u8]| sink(b));
    };
    for c in 0..5 {
        send(&mut checker, c, &mut sink);
    }
    // Three repeats: the third bad status in the window makes the link INVALID.
    for _ in 0..2 {
        send(&mut checker, 4, &mut sink);
    }
    assert!(checker.link_valid());
    send(&mut checker, 4, &mut sink);
    assert!(!checker.link_valid());
    // 18 good statuses later the first repeat leaves the window: VALID again.
    for c in 5..22 {
        send(&mut checker, c, &mut sink);
        assert!(!checker.link_valid(), "counter {c}");
    }
    send(&mut checker, 22, &mut sink);
    assert!(checker.link_valid());
    let mut rx = Deframer::new();
    let kinds: Vec<_> = answers(&mut rx, &out)
        .into_iter()
        .filter_map(|m| match m {
            Message::Event(Tagged {
                event: e @ (LinkEvent::LinkFault { .. } | LinkEvent::LinkRestored { .. }),
                counter,
            }) => Some((counter, e)),
            _ => None,
        })
        .collect();
    assert_eq!(
        kinds,
        [
            (4, LinkEvent::LinkFault { bad: 3 }),
            (22, LinkEvent::LinkRestored { bad: 2 })
        ]
    );
    let _ = Event::Comfort;
}

/// A doer that restarts (its counter back to 0) and a checker reset mid-route: the first is a
/// WRONGSEQUENCE and a new segment; the second leaves frames unmonitored until a start.
#[test]
fn doer_restart_and_checker_reset() {
    let mut checker: Checker = Checker::new(LinkConfig::DEFAULT).unwrap();
    let mut out = Vec::new();
    let mut sink = |b: &[u8]| out.extend_from_slice(b);
    checker.receive(&encoded(&Message::Start(Config::DEFAULT), 0), 0, &mut sink);
    let f = Frame::default();
    for c in 100..130u16 {
        checker.receive(&encoded(&Message::Frame(f), c), u64::from(c), &mut sink);
    }
    for c in 0..30u16 {
        checker.receive(
            &encoded(&Message::Frame(f), c),
            200 + u64::from(c),
            &mut sink,
        );
    }
    let s = checker.status();
    assert_eq!(s.counts.get(CheckStatus::WrongSequence), 1);
    assert_eq!((s.accepted, s.segments), (59, 2));

    let mut fresh: Checker = Checker::new(LinkConfig::DEFAULT).unwrap();
    for c in 30..40u16 {
        fresh.receive(&encoded(&Message::Frame(f), c), u64::from(c), &mut sink);
    }
    let s = fresh.status();
    assert_eq!((s.accepted, s.route), (0, link::RouteState::Idle));
    assert_eq!(s.counts.get(CheckStatus::Ok), 10);
}
