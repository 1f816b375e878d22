//! One run played to a checker, route by route: the start (repeated until a status answers
//! it), the frames (paced, faults injected), the end (repeated until the summary answers it);
//! then the replay of the frames the checker accepted, cut into the segments it announced, and
//! the route's `link` figures.
//!
//! Which frames the checker accepted is read from a *shadow* checker that takes exactly the
//! bytes written to the wire, message by message, without a clock (a frame's acceptance does not
//! depend on time; a timeout only cuts a segment, and the real checker announces every cut with
//! a `segment` event). The replay itself is a fresh [`Monitor`] per segment, independent of the
//! checker's code.

use std::collections::HashMap;
use std::io::{Read, Write};
use std::sync::mpsc::{self, Receiver};
use std::time::{Duration, Instant};

use monitor_core::link::{
    self, CheckStatus, Checker, Deframer, LinkConfig, LinkEvent, LinkSummary, Message, RouteState,
    StatusCounts,
};
use monitor_core::{Config, Event, Frame, Monitor};

use crate::live_link::inject::Inject;
use crate::live_link::transport::Connection;

named_enum! {
    /// How fast frames are sent (`--pace`, `pace=`).
    #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
    #[serde(rename_all = "lowercase")]
    pub enum Pace {
        /// One frame per frame period, as the vehicle makes them.
        Realtime = "realtime",
        /// As fast as the stream takes them (the checker's reading paces the writer).
        #[default]
        Fast = "fast",
    }
}

/// The check statuses of a route's frame messages, named as the report names them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
#[allow(non_snake_case, missing_docs)]
pub struct Statuses {
    pub OK: u32,
    pub OKSOMELOST: u32,
    pub WRONGSEQUENCE: u32,
    pub REPEATED: u32,
    pub ERROR: u32,
    pub NONEWDATA: u32,
}

impl From<&StatusCounts> for Statuses {
    fn from(c: &StatusCounts) -> Self {
        Statuses {
            OK: c.get(CheckStatus::Ok),
            OKSOMELOST: c.get(CheckStatus::OkSomeLost),
            WRONGSEQUENCE: c.get(CheckStatus::WrongSequence),
            REPEATED: c.get(CheckStatus::Repeated),
            ERROR: c.get(CheckStatus::Error),
            NONEWDATA: c.get(CheckStatus::NoNewData),
        }
    }
}

/// Latency from a frame's last byte written to its events read, ms.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct Latency {
    /// Median over the route's events (`null` without events).
    pub median: Option<f64>,
    /// Largest.
    pub max: Option<f64>,
}

/// A route's `link` object in the report.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct LinkFigures {
    /// The checker's events and summary equal the replay's.
    pub equal: bool,
    /// Frames the checker accepted (its summary's frames).
    pub accepted: u32,
    /// Segments the checker started.
    pub segments: u32,
    /// Monitor events received from the checker.
    pub events: usize,
    /// Monitor events of the replay over the accepted frames.
    pub replay_events: usize,
    /// Check statuses of the route's frame messages.
    pub statuses: Statuses,
    /// Route time (s, the frame's index times the period) of each `link_fault`.
    pub link_faults: Vec<f64>,
    /// Latency of the events.
    pub latency_ms: Latency,
    /// Frames lost inside segments (the checker's summary).
    pub gaps: u32,
    /// What differs, when not equal.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub differs: Option<String>,
}

/// One route's result.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct RouteLink {
    /// The route id (a log's name).
    pub route_id: String,
    /// Frames of the route.
    pub frames: usize,
    /// The figures.
    pub link: LinkFigures,
}

/// Why playing stopped.
#[derive(Debug, thiserror::Error)]
pub enum PlayError {
    /// Writing to the checker failed.
    #[error("writing to the checker: {0}")]
    Write(#[source] std::io::Error),
    /// The checker did not answer a start or an end.
    #[error("route {route}: the checker did not answer the {what} ({tries} tries, {wait} s apart); is it running and reading this stream?")]
    NoAnswer {
        /// The route.
        route: String,
        /// `start` or `end`.
        what: &'static str,
        /// Messages sent.
        tries: u32,
        /// Seconds waited for each.
        wait: f64,
    },
    /// The checker refused the configuration.
    #[error("route {route}: the checker refused the monitor's configuration (check --set and the profile)")]
    Refused {
        /// The route.
        route: String,
    },
}

/// Seconds to wait for the answer to a start or an end before sending it again.
const ANSWER_WAIT: f64 = 2.0;
/// Starts or ends sent before giving up.
const TRIES: u32 = 5;

/// Plays routes over one connection.
pub struct Player {
    writer: Box<dyn Write + Send>,
    incoming: Receiver<(Instant, Vec<u8>)>,
    rx: Deframer,
    /// Messages read but not yet used.
    pending: std::collections::VecDeque<(Instant, Message)>,
    shadow: Checker,
    counters: (u16, u16, u16),
    pace: Pace,
    inject: Inject,
    tap_sent: Option<std::fs::File>,
    routes_played: usize,
    child: Option<std::process::Child>,
}

impl Player {
    /// A player over `conn` to a checker with the settings `link`; `tap` receives a copy of every byte written (`sent.bin`) and read
    /// (`received.bin`).
    ///
    /// # Errors
    /// Creating the tap files.
    pub fn new(
        conn: Connection,
        pace: Pace,
        inject: Inject,
        link: LinkConfig,
        tap: Option<&std::path::Path>,
    ) -> std::io::Result<Self> {
        let (tap_sent, mut tap_received) = match tap {
            Some(dir) => {
                std::fs::create_dir_all(dir)?;
                (
                    Some(std::fs::File::create(dir.join("sent.bin"))?),
                    Some(std::fs::File::create(dir.join("received.bin"))?),
                )
            }
            None => (None, None),
        };
        let (tx, incoming) = mpsc::channel();
        let mut reader = conn.reader;
        std::thread::spawn(move || {
            let mut buf = [0u8; 4096];
            loop {
                match reader.read(&mut buf) {
                    Ok(0) | Err(_) => break,
                    Ok(n) => {
                        if let Some(f) = &mut tap_received {
                            let _ = f.write_all(&buf[..n]);
                        }
                        if tx.send((Instant::now(), buf[..n].to_vec())).is_err() {
                            break;
                        }
                    }
                }
            }
        });
        Ok(Player {
            writer: conn.writer,
            incoming,
            rx: Deframer::new(),
            pending: Default::default(),
            shadow: Checker::new(link).map_err(std::io::Error::other)?,
            counters: (0, 0, 0),
            pace,
            inject,
            tap_sent,
            routes_played: 0,
            child: conn.child,
        })
    }

    fn write(&mut self, bytes: &[u8]) -> Result<(), PlayError> {
        self.writer.write_all(bytes).map_err(PlayError::Write)?;
        if let Some(f) = &mut self.tap_sent {
            f.write_all(bytes).map_err(PlayError::Write)?;
        }
        Ok(())
    }

    /// Writes `bytes` and feeds them to the shadow; returns the shadow's accepted delta.
    fn send(&mut self, bytes: &[u8]) -> Result<u32, PlayError> {
        self.write(bytes)?;
        let before = self.shadow.status().accepted;
        self.shadow.receive(bytes, 0, &mut |_: &[u8]| {});
        Ok(self.shadow.status().accepted.wrapping_sub(before))
    }

    /// Reads what has arrived; with a `deadline`, waits until then for at least one message.
    fn pump(&mut self, deadline: Option<Instant>) {
        loop {
            let got = match deadline {
                Some(d) => self
                    .incoming
                    .recv_timeout(d.saturating_duration_since(Instant::now()))
                    .ok(),
                None => self.incoming.try_recv().ok(),
            };
            let Some((t, bytes)) = got else {
                return;
            };
            for b in bytes {
                if let Some(Ok(m)) = self.rx.push(b) {
                    // A message of the checker's that fails its check is dropped here, as the
                    // checker drops the doer's.
                    if let Ok((_, msg)) = link::decode(m) {
                        self.pending.push_back((t, msg));
                    }
                }
            }
            if deadline.is_some() && !self.pending.is_empty() {
                return;
            }
        }
    }

    /// Waits for a message that `want` takes, keeping every message in `seen`.
    fn await_answer(
        &mut self,
        want: impl Fn(&Message) -> bool,
        seen: &mut Vec<(Instant, Message)>,
    ) -> Option<Message> {
        let deadline = Instant::now() + Duration::from_secs_f64(ANSWER_WAIT);
        loop {
            while let Some((t, m)) = self.pending.pop_front() {
                seen.push((t, m));
                if want(&m) {
                    return Some(m);
                }
            }
            if Instant::now() >= deadline {
                return None;
            }
            self.pump(Some(deadline));
        }
    }

    /// Plays one route and compares the checker's answers with the replay.
    ///
    /// # Errors
    /// [`PlayError`]: the stream failed, or the checker stopped answering.
    pub fn play(
        &mut self,
        route_id: &str,
        config: Config,
        frames: &[Frame],
    ) -> Result<RouteLink, PlayError> {
        let route_index = self.routes_played;
        self.routes_played += 1;
        let mut seen: Vec<(Instant, Message)> = Vec::new();
        let mut buf = [0u8; link::MAX_ENCODED];

        // Start, until a status answers it (a repeat is a new message: a new counter).
        let mut answered = None;
        for _ in 0..TRIES {
            let c = self.counters.0;
            self.counters.0 = c.wrapping_add(1);
            let n = link::encode(&Message::Start(config), c, &mut buf);
            self.send(&buf[..n])?;
            self.writer.flush().map_err(PlayError::Write)?;
            answered = self.await_answer(|m| matches!(m, Message::Status(_)), &mut seen);
            if answered.is_some() {
                break;
            }
        }
        match answered {
            None => {
                return Err(PlayError::NoAnswer {
                    route: route_id.into(),
                    what: "start",
                    tries: TRIES,
                    wait: ANSWER_WAIT,
                })
            }
            Some(Message::Status(s)) if s.route == RouteState::Refused => {
                return Err(PlayError::Refused {
                    route: route_id.into(),
                })
            }
            Some(_) => {}
        }
        seen.clear();

        // Frames.
        let first = self.counters.1;
        let mut plan = self
            .inject
            .plan(route_index, frames.len(), f64::from(config.dt));
        let mut accepted: Vec<(u16, usize)> = Vec::new();
        let mut sent_at: HashMap<u16, Instant> = HashMap::new();
        let t0 = Instant::now();
        let dt = Duration::from_secs_f64(f64::from(config.dt));
        for (i, f) in frames.iter().enumerate() {
            let c = self.counters.1;
            self.counters.1 = c.wrapping_add(1);
            if self.pace == Pace::Realtime {
                let due = t0 + dt * i as u32;
                let now = Instant::now();
                if due > now {
                    std::thread::sleep(due - now);
                }
            }
            let n = link::encode(&Message::Frame(*f), c, &mut buf);
            let sent = plan.frame(i, c, &buf[..n]);
            if sent.pause > 0.0 {
                self.writer.flush().map_err(PlayError::Write)?;
                std::thread::sleep(Duration::from_secs_f64(sent.pause));
            }
            self.send_pieces(&sent.pieces, first, &mut accepted, &mut sent_at)?;
            self.pump(None);
        }
        let rest = plan.flush();
        self.send_pieces(&rest.pieces, first, &mut accepted, &mut sent_at)?;

        // End, until the summary answers it.
        let mut summary = None;
        for _ in 0..TRIES {
            let c = self.counters.2;
            self.counters.2 = c.wrapping_add(1);
            let m = Message::End {
                frames: frames.len() as u32,
            };
            let n = link::encode(&m, c, &mut buf);
            self.send(&buf[..n])?;
            self.writer.flush().map_err(PlayError::Write)?;
            if let Some(Message::Summary(s)) =
                self.await_answer(|m| matches!(m, Message::Summary(_)), &mut seen)
            {
                summary = Some(s);
                break;
            }
        }
        let Some(summary) = summary else {
            return Err(PlayError::NoAnswer {
                route: route_id.into(),
                what: "end",
                tries: TRIES,
                wait: ANSWER_WAIT,
            });
        };
        Ok(RouteLink {
            route_id: route_id.into(),
            frames: frames.len(),
            link: figures(config, frames, first, &accepted, &seen, &sent_at, &summary),
        })
    }

    fn send_pieces(
        &mut self,
        pieces: &[(Vec<u8>, Option<u16>)],
        first: u16,
        accepted: &mut Vec<(u16, usize)>,
        sent_at: &mut HashMap<u16, Instant>,
    ) -> Result<(), PlayError> {
        // Each piece carries its frame's counter when it goes out intact (the injector knows).
        for (bytes, counter) in pieces {
            let newly = self.send(bytes)?;
            if newly > 0 {
                let c = self.shadow.status().last_counter;
                accepted.push((c, usize::from(c.wrapping_sub(first))));
            }
            if self.pace == Pace::Realtime {
                self.writer.flush().map_err(PlayError::Write)?;
            }
            if let Some(c) = counter {
                sent_at.insert(*c, Instant::now());
            }
        }
        Ok(())
    }

    /// Closes the stream and waits for an `exec:` child.
    pub fn close(mut self) {
        let _ = self.writer.flush();
        drop(self.writer);
        if let Some(mut c) = self.child.take() {
            let _ = c.wait();
        }
    }
}

/// The replay over the accepted frames cut at the checker's segments, and the comparison.
fn figures(
    config: Config,
    frames: &[Frame],
    first: u16,
    accepted: &[(u16, usize)],
    seen: &[(Instant, Message)],
    sent_at: &HashMap<u16, Instant>,
    summary: &LinkSummary,
) -> LinkFigures {
    let mut events = Vec::new();
    let mut cuts = Vec::new();
    let mut faults = Vec::new();
    let mut latencies = Vec::new();
    for (t, m) in seen {
        let Message::Event(e) = m else { continue };
        match e.event {
            LinkEvent::Monitor(ev) => {
                events.push((e.counter, ev));
                if let Some(s) = sent_at.get(&e.counter) {
                    latencies.push(t.saturating_duration_since(*s).as_secs_f64() * 1e3);
                }
            }
            LinkEvent::Segment { .. } => cuts.push(e.counter),
            LinkEvent::LinkFault { .. } => {
                let index = e.counter.wrapping_sub(first);
                // Rounded to the microsecond: the f32 period's bits are not the decimal one.
                let t = f64::from(index) * f64::from(config.dt);
                faults.push((t * 1e6).round() / 1e6);
            }
            LinkEvent::LinkRestored { .. } => {}
        }
    }
    // Replay: a fresh monitor per segment.
    let mut replay: Vec<(u16, Event)> = Vec::new();
    let mut sum = LinkSummary::default();
    let mut differs = None;
    let mut cut = cuts.iter().peekable();
    let mut seg: Option<(Monitor, u16)> = None;
    let close = |seg: &mut Option<(Monitor, u16)>,
                 replay: &mut Vec<(u16, Event)>,
                 sum: &mut LinkSummary| {
        if let Some((mut m, last)) = seg.take() {
            if let Ok(done) = m.finish() {
                replay.extend(done.events.iter().map(|e| (last, *e)));
                sum.add_segment(&done.summary);
            }
        }
    };
    for &(c, index) in accepted {
        if cut.peek() == Some(&&c) {
            cut.next();
            close(&mut seg, &mut replay, &mut sum);
            match Monitor::new(config) {
                Ok(m) => seg = Some((m, c)),
                Err(e) => {
                    differs = Some(format!("the replay refused the configuration: {e}"));
                    break;
                }
            }
        }
        let Some(f) = frames.get(index) else {
            differs = Some(format!("accepted counter {c} is not a frame of the route"));
            break;
        };
        let Some((m, last)) = &mut seg else {
            differs = Some(format!("frame {c} accepted before any segment"));
            break;
        };
        *last = c;
        if let Ok(ev) = m.push(f) {
            replay.extend(ev.iter().map(|e| (c, *e)));
        }
    }
    close(&mut seg, &mut replay, &mut sum);
    if differs.is_none() && cut.next().is_some() {
        differs = Some("a segment started at a frame the replay did not accept".into());
    }
    if differs.is_none() && events != replay {
        let at = events.iter().zip(&replay).position(|(a, b)| a != b);
        differs = Some(match at {
            Some(i) => format!("event {i}: checker {:?}, replay {:?}", events[i], replay[i]),
            None => format!(
                "{} events from the checker, {} in the replay",
                events.len(),
                replay.len()
            ),
        });
    }
    if differs.is_none() && summary.route != sum.route {
        differs = Some("the summary's counts differ from the replay's".into());
    }
    if differs.is_none() && summary.segments != sum.segments {
        differs = Some(format!(
            "{} segments in the summary, {} replayed",
            summary.segments, sum.segments
        ));
    }
    latencies.sort_by(f64::total_cmp);
    let median = (!latencies.is_empty()).then(|| {
        let n = latencies.len();
        if n % 2 == 1 {
            latencies[n / 2]
        } else {
            (latencies[n / 2 - 1] + latencies[n / 2]) / 2.0
        }
    });
    LinkFigures {
        equal: differs.is_none(),
        accepted: summary.route.frames,
        segments: summary.segments,
        events: events.len(),
        replay_events: replay.len(),
        statuses: Statuses::from(&summary.counts),
        link_faults: faults,
        latency_ms: Latency {
            median,
            max: latencies.last().copied(),
        },
        gaps: summary.gaps,
        differs,
    }
}
