//! The checker: the safety controller's side of the link. It gives every frame message
//! Profile 4's check status, feeds the frames it accepts to a [`Monitor`], cuts the route into
//! segments where it lost sight of the doer, keeps the VALID/INVALID window, and answers with
//! event, status and summary messages (docs/SCORE.md, "Live link").
//!
//! Memory is fixed: the monitor, one receive buffer of the largest message, the window (a
//! 32-bit mask) and a few counters. Time per byte is O(1) except at a message's end, where the
//! CRC runs over at most [`crate::link::MAX_MESSAGE`] bytes and the monitor takes one frame.

use crate::config::Config;
use crate::event::Events;
use crate::frame::Frame;
use crate::link::framing::{Deframer, MAX_ENCODED};
use crate::link::payload::{
    self, LinkEvent, LinkState, LinkSummary, Message, RouteState, Status, Tagged,
};
use crate::monitor::Monitor;

/// The check status of one frame message, as AUTOSAR E2E Profile 4 names them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum CheckStatus {
    /// Counter +1 (or the first frame message the checker ever received): accepted.
    Ok,
    /// Counter +2 ..= `max_delta`: accepted; the frames between are lost (they count in gaps).
    OkSomeLost,
    /// A larger jump (or a step back): dropped; the next accepted frame starts a new segment.
    WrongSequence,
    /// The same counter again: dropped.
    Repeated,
    /// Length, data id, CRC, COBS or the payload's layout wrong: dropped.
    Error,
    /// No frame for `timeout` frame periods: the next accepted frame starts a new segment.
    NoNewData,
}

impl CheckStatus {
    /// Every status, in the order of the wire and the report.
    pub const ALL: [CheckStatus; 6] = [
        CheckStatus::Ok,
        CheckStatus::OkSomeLost,
        CheckStatus::WrongSequence,
        CheckStatus::Repeated,
        CheckStatus::Error,
        CheckStatus::NoNewData,
    ];

    /// The status's name as Profile 4 and the report spell it.
    ///
    /// ```
    /// assert_eq!(monitor_core::link::CheckStatus::OkSomeLost.name(), "OKSOMELOST");
    /// ```
    pub const fn name(self) -> &'static str {
        match self {
            CheckStatus::Ok => "OK",
            CheckStatus::OkSomeLost => "OKSOMELOST",
            CheckStatus::WrongSequence => "WRONGSEQUENCE",
            CheckStatus::Repeated => "REPEATED",
            CheckStatus::Error => "ERROR",
            CheckStatus::NoNewData => "NONEWDATA",
        }
    }

    /// The frame goes to the monitor (`OK`, `OKSOMELOST`).
    pub const fn accepted(self) -> bool {
        matches!(self, CheckStatus::Ok | CheckStatus::OkSomeLost)
    }

    /// The status counts against the link in the window.
    pub const fn bad(self) -> bool {
        !self.accepted()
    }

    const fn index(self) -> usize {
        self as usize
    }
}

/// How many messages got each check status.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct StatusCounts([u32; 6]);

impl StatusCounts {
    /// The count of `status`.
    ///
    /// ```
    /// use monitor_core::link::{CheckStatus, StatusCounts};
    /// assert_eq!(StatusCounts::default().get(CheckStatus::Error), 0);
    /// ```
    pub const fn get(&self, status: CheckStatus) -> u32 {
        self.0[status.index()]
    }

    /// Sets the count of `status`.
    pub fn set(&mut self, status: CheckStatus, n: u32) {
        self.0[status.index()] = n;
    }

    fn add(&mut self, status: CheckStatus) {
        let n = &mut self.0[status.index()];
        *n = n.saturating_add(1);
    }
}

/// The link's settings (the `link.*` settings): Profile 4's counter tolerance and timeout, and
/// the VALID/INVALID window.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct LinkConfig {
    /// Largest counter step still accepted (`link.max_delta`, default 3): steps 2 ..= this are
    /// `OKSOMELOST`.
    pub max_delta: u16,
    /// Frame periods without a frame before `NONEWDATA` (`link.timeout`, default 3).
    pub timeout: u16,
    /// Statuses the link state is judged over (`link.window`, default 20; 1 ..= 32).
    pub window: u8,
    /// Bad statuses in the window still `VALID` (`link.max_errors`, default 2; below `window`).
    pub max_errors: u8,
}

/// Why a [`LinkConfig`] was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum LinkConfigError {
    /// `max_delta` must be at least 1.
    MaxDelta,
    /// `timeout` must be at least 1 frame period.
    Timeout,
    /// `window` must lie in 1 ..= 32.
    Window,
    /// `max_errors` must be below `window`.
    MaxErrors,
    /// The checker's monitor cannot hold the default configuration (capacity below 20).
    Capacity,
}

impl core::fmt::Display for LinkConfigError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            LinkConfigError::MaxDelta => "link.max_delta must be at least 1",
            LinkConfigError::Timeout => "link.timeout must be at least 1 frame period",
            LinkConfigError::Window => "link.window must lie in 1..=32",
            LinkConfigError::MaxErrors => "link.max_errors must be below link.window",
            LinkConfigError::Capacity => "the checker's monitor must hold 20 frames a chunk",
        })
    }
}

impl core::error::Error for LinkConfigError {}

impl LinkConfig {
    /// The defaults: `max_delta` 3, `timeout` 3 frame periods, `window` 20, `max_errors` 2.
    pub const DEFAULT: LinkConfig = LinkConfig {
        max_delta: 3,
        timeout: 3,
        window: 20,
        max_errors: 2,
    };

    /// Checks the settings.
    ///
    /// ```
    /// use monitor_core::link::{LinkConfig, LinkConfigError};
    /// let bad = LinkConfig { window: 40, ..LinkConfig::DEFAULT };
    /// assert_eq!(bad.validate(), Err(LinkConfigError::Window));
    /// ```
    pub const fn validate(&self) -> Result<(), LinkConfigError> {
        if self.max_delta < 1 {
            return Err(LinkConfigError::MaxDelta);
        }
        if self.timeout < 1 {
            return Err(LinkConfigError::Timeout);
        }
        if self.window < 1 || self.window > 32 {
            return Err(LinkConfigError::Window);
        }
        if self.max_errors >= self.window {
            return Err(LinkConfigError::MaxErrors);
        }
        Ok(())
    }

    /// Profile 4's check status of a frame message with counter `counter` after `last` (the
    /// counter of the last frame message that passed its check; `None` before the first).
    ///
    /// ```
    /// use monitor_core::link::{CheckStatus, LinkConfig};
    /// let c = LinkConfig::DEFAULT;
    /// assert_eq!(c.status(Some(65535), 0), CheckStatus::Ok);        // wrapping
    /// assert_eq!(c.status(Some(7), 10), CheckStatus::OkSomeLost);
    /// assert_eq!(c.status(Some(7), 11), CheckStatus::WrongSequence);
    /// assert_eq!(c.status(Some(7), 6), CheckStatus::WrongSequence); // a reordered frame
    /// assert_eq!(c.status(Some(7), 7), CheckStatus::Repeated);
    /// assert_eq!(c.status(None, 1234), CheckStatus::Ok);
    /// ```
    pub const fn status(&self, last: Option<u16>, counter: u16) -> CheckStatus {
        let Some(last) = last else {
            return CheckStatus::Ok;
        };
        match counter.wrapping_sub(last) {
            0 => CheckStatus::Repeated,
            1 => CheckStatus::Ok,
            d if d <= self.max_delta => CheckStatus::OkSomeLost,
            _ => CheckStatus::WrongSequence,
        }
    }
}

impl Default for LinkConfig {
    fn default() -> Self {
        LinkConfig::DEFAULT
    }
}

/// The last `window` statuses, as a mask of the bad ones.
#[derive(Clone, Copy, Debug, Default)]
struct Window {
    bad: u32,
}

impl Window {
    fn push(&mut self, bad: bool, window: u8) {
        let mask = if window >= 32 {
            u32::MAX
        } else {
            (1u32 << window) - 1
        };
        self.bad = ((self.bad << 1) | bad as u32) & mask;
    }

    fn count(&self) -> u32 {
        self.bad.count_ones()
    }
}

/// Counters of the checker's own messages, one per data id.
#[derive(Clone, Copy, Debug, Default)]
struct TxCounters {
    event: u16,
    status: u16,
    summary: u16,
}

/// The checker of one link: owns a [`Monitor`] of capacity `N` and fixed buffers.
///
/// Feed it the bytes received ([`Checker::receive`]) and call [`Checker::poll`] now and then
/// (for the timeout); each answer goes to `out` as encoded bytes, ready for the wire. The clock
/// is the caller's (microseconds, monotonic): a host's `Instant`, a Cortex-M's timer.
///
/// ```
/// use monitor_core::link::{self, Checker, LinkConfig, Message};
/// use monitor_core::{Config, Frame};
/// let mut checker: Checker = Checker::new(LinkConfig::DEFAULT).unwrap();
/// let mut buf = [0u8; link::MAX_ENCODED];
/// let mut sent = 0;
/// let mut out = |bytes: &[u8]| sent += bytes.len();
/// let n = link::encode(&Message::Start(Config::DEFAULT), 0, &mut buf);
/// checker.receive(&buf[..n], 0, &mut out);
/// for c in [0u16, 1, 2, 5, 6] {    // 3 and 4 lost: a jump of 3 is still OKSOMELOST
///     let n = link::encode(&Message::Frame(Frame::default()), c, &mut buf);
///     checker.receive(&buf[..n], 1000 * u64::from(c), &mut out);
/// }
/// let s = checker.status();
/// assert_eq!((s.accepted, s.segments), (5, 1));
/// // 3 frame periods (150 ms) without a frame: NONEWDATA, and the next frame a new segment.
/// checker.poll(6_000 + 150_000, &mut out);
/// assert_eq!(checker.status().counts.get(link::CheckStatus::NoNewData), 1);
/// ```
#[derive(Clone, Debug)]
pub struct Checker<const N: usize = { crate::DEFAULT_CAPACITY }> {
    link: LinkConfig,
    monitor: Monitor<N>,
    rx: Deframer,
    tx: TxCounters,
    route: RouteState,
    /// Last counter of each doer data id that passed its check (Profile 4: per data id).
    last_frame: Option<u16>,
    last_start: Option<u16>,
    last_end: Option<u16>,
    window: Window,
    valid: bool,
    counts: StatusCounts,
    accepted: u32,
    /// The route so far: finished segments' counts, gaps, segments.
    summary: LinkSummary,
    /// Counter of the current segment's last accepted frame (`None`: no segment yet).
    seg_last: Option<u16>,
    /// The next accepted frame starts a new segment.
    cut: bool,
    /// Time of the route's last frame message (or of the last `NONEWDATA`), µs.
    last_time: Option<u64>,
    timeout_us: u64,
    /// Frame statuses per status message (one second of frames).
    status_every: u32,
    since_status: u32,
}

impl<const N: usize> Checker<N> {
    /// A checker with no route yet, after checking `link`.
    ///
    /// # Errors
    /// [`LinkConfigError`]; [`LinkConfigError::Capacity`] for `N` below the default chunk.
    pub fn new(link: LinkConfig) -> Result<Self, LinkConfigError> {
        link.validate()?;
        Ok(Checker {
            link,
            // Replaced by the first start's configuration; never pushed before.
            monitor: Monitor::new(Config::DEFAULT).map_err(|_| LinkConfigError::Capacity)?,
            rx: Deframer::new(),
            tx: TxCounters::default(),
            route: RouteState::Idle,
            last_frame: None,
            last_start: None,
            last_end: None,
            window: Window::default(),
            valid: true,
            counts: StatusCounts::default(),
            accepted: 0,
            summary: LinkSummary::default(),
            seg_last: None,
            cut: false,
            last_time: None,
            timeout_us: 0,
            status_every: 20,
            since_status: 0,
        })
    }

    /// The link settings.
    pub const fn link_config(&self) -> &LinkConfig {
        &self.link
    }

    /// `true` while the link is `VALID` (what the `link_fault` pin shows, inverted).
    pub const fn link_valid(&self) -> bool {
        self.valid
    }

    /// The status message the checker would send now.
    pub fn status(&self) -> Status {
        Status {
            link: if self.valid {
                LinkState::Valid
            } else {
                LinkState::Invalid
            },
            route: self.route,
            last_counter: self.last_frame.unwrap_or(0),
            counts: self.counts,
            accepted: self.accepted,
            segments: self.summary.segments
                + (self.route == RouteState::Running && self.seg_last.is_some()) as u32,
        }
    }

    /// Takes received bytes at time `now_us`; every answer goes to `out` (encoded, delimited).
    pub fn receive(&mut self, bytes: &[u8], now_us: u64, out: &mut impl FnMut(&[u8])) {
        for &b in bytes {
            self.receive_byte(b, now_us, out);
        }
    }

    /// Takes one received byte (what a UART interrupt hands over).
    pub fn receive_byte(&mut self, byte: u8, now_us: u64, out: &mut impl FnMut(&[u8])) {
        let decoded = match self.rx.push(byte) {
            None => return,
            Some(Err(_)) => Err(()),
            Some(Ok(m)) => payload::decode(m).map_err(|_| ()),
        };
        match decoded {
            Err(()) => self.judge(CheckStatus::Error, now_us, out),
            Ok((h, Message::Frame(f))) => self.frame(h.counter, &f, now_us, out),
            Ok((h, Message::Start(c))) => self.start(h.counter, c, out),
            Ok((h, Message::End { .. })) => self.end(h.counter, out),
            // The checker's own messages coming back (a loop-back wiring): not for it.
            Ok(_) => self.judge(CheckStatus::Error, now_us, out),
        }
    }

    /// Checks the timeout at time `now_us`: with a route running and no frame message for
    /// `timeout` frame periods, the status is `NONEWDATA` (once per timeout), a status message
    /// is sent, and the next accepted frame starts a new segment.
    pub fn poll(&mut self, now_us: u64, out: &mut impl FnMut(&[u8])) {
        if self.route != RouteState::Running {
            return;
        }
        let Some(t) = self.last_time else {
            return;
        };
        if now_us.saturating_sub(t) >= self.timeout_us {
            self.last_time = Some(now_us);
            self.cut = true;
            self.judge(CheckStatus::NoNewData, now_us, out);
            self.send_status(out);
        }
    }

    /// The current route's timeout in µs: `link.timeout` frame periods of its start's `dt` (0
    /// before the first start). A checker whose clock counts received messages (one frame
    /// period each) reads its period here.
    ///
    /// ```
    /// use monitor_core::link::{Checker, LinkConfig};
    /// let checker: Checker = Checker::new(LinkConfig::DEFAULT).unwrap();
    /// assert_eq!(checker.timeout_us(), 0);
    /// ```
    pub const fn timeout_us(&self) -> u64 {
        self.timeout_us
    }

    /// The time by which [`Checker::poll`] must run for `NONEWDATA` to be on time (`None`
    /// while no timeout runs): a firmware sets its timer to it.
    pub fn deadline(&self) -> Option<u64> {
        match (self.route, self.last_time) {
            (RouteState::Running, Some(t)) => Some(t.saturating_add(self.timeout_us)),
            _ => None,
        }
    }

    fn frame(&mut self, counter: u16, f: &Frame, now_us: u64, out: &mut impl FnMut(&[u8])) {
        if f.validate().is_err() {
            // The doer sent numbers the monitor refuses: wrong data, though the link carried it.
            self.judge(CheckStatus::Error, now_us, out);
            return;
        }
        let status = self.link.status(self.last_frame, counter);
        // Profile 4: every message that passed its check sets the last counter.
        self.last_frame = Some(counter);
        if self.route == RouteState::Running {
            self.last_time = Some(now_us);
        }
        if status == CheckStatus::WrongSequence {
            self.cut = true;
        }
        if status.accepted() && self.route == RouteState::Running {
            self.monitor_frame(counter, f, out);
        }
        self.judge(status, now_us, out);
        if self.route == RouteState::Running {
            self.since_status += 1;
            if self.since_status >= self.status_every {
                self.send_status(out);
            }
        }
    }

    fn monitor_frame(&mut self, counter: u16, f: &Frame, out: &mut impl FnMut(&[u8])) {
        match self.seg_last {
            Some(last) if !self.cut => {
                let lost = u32::from(counter.wrapping_sub(last)).saturating_sub(1);
                self.summary.gaps = self.summary.gaps.saturating_add(lost);
            }
            _ => {
                self.close_segment(out);
                self.cut = false;
                let index = self.summary.segments;
                self.send_event(counter, LinkEvent::Segment { index }, out);
            }
        }
        // A valid frame in a running, unfinished route: push cannot fail but for u32::MAX
        // frames, and then the frame is dropped like any other the monitor refuses.
        if let Ok(events) = self.monitor.push(f) {
            self.accepted = self.accepted.saturating_add(1);
            self.seg_last = Some(counter);
            self.send_events(counter, &events, out);
        }
    }

    /// Finishes the current segment's monitor (if one runs), sends its last events, adds its
    /// counts to the route's, and starts the monitor afresh.
    fn close_segment(&mut self, out: &mut impl FnMut(&[u8])) {
        let Some(last) = self.seg_last.take() else {
            return;
        };
        if let Ok(done) = self.monitor.finish() {
            self.send_events(last, &done.events, out);
            self.summary.add_segment(&done.summary);
        }
        self.monitor.reset();
    }

    fn start(&mut self, counter: u16, config: Config, out: &mut impl FnMut(&[u8])) {
        let repeated = self.last_start == Some(counter);
        self.last_start = Some(counter);
        if !repeated {
            // A new route: the monitor, the segments and the window start afresh; the last
            // counters of each data id run on.
            self.route = match Monitor::<N>::new(config) {
                Ok(m) => {
                    self.monitor = m;
                    RouteState::Running
                }
                Err(_) => RouteState::Refused,
            };
            self.counts = StatusCounts::default();
            self.accepted = 0;
            self.summary = LinkSummary::default();
            self.seg_last = None;
            self.cut = false;
            self.last_time = None;
            self.window = Window::default();
            self.since_status = 0;
            let dt = config.dt;
            // dt was validated to 1 ms ..= 1 s when Running; the casts saturate otherwise.
            self.timeout_us = (f32::from(self.link.timeout) * dt * 1e6) as u64;
            self.status_every = ((1.0 / dt) as u32).max(1);
            if !self.valid {
                self.valid = true;
                self.send_event(
                    self.last_frame.unwrap_or(0),
                    LinkEvent::LinkRestored { bad: 0 },
                    out,
                );
            }
        }
        // The answer to a start (a repeated one too: the first answer may have been lost).
        self.send_status(out);
    }

    fn end(&mut self, counter: u16, out: &mut impl FnMut(&[u8])) {
        let repeated = self.last_end == Some(counter);
        self.last_end = Some(counter);
        match self.route {
            RouteState::Running if !repeated => {
                self.close_segment(out);
                self.route = RouteState::Finished;
                self.last_time = None;
                self.send_summary(out);
            }
            // A repeated end (its summary was lost on the way back): the same summary again.
            RouteState::Finished => self.send_summary(out),
            _ => self.send_status(out),
        }
    }

    /// Counts a status, slides the window, and emits `link_fault` / `link_restored` when the
    /// state changes.
    fn judge(&mut self, status: CheckStatus, _now_us: u64, out: &mut impl FnMut(&[u8])) {
        self.counts.add(status);
        self.window.push(status.bad(), self.link.window);
        let bad = self.window.count();
        let valid = bad <= u32::from(self.link.max_errors);
        let counter = self.last_frame.unwrap_or(0);
        if self.valid && !valid {
            self.valid = false;
            self.send_event(counter, LinkEvent::LinkFault { bad }, out);
        } else if !self.valid && valid {
            self.valid = true;
            self.send_event(counter, LinkEvent::LinkRestored { bad }, out);
        }
    }

    fn send_events(&mut self, counter: u16, events: &Events, out: &mut impl FnMut(&[u8])) {
        for e in events {
            self.send_event(counter, LinkEvent::Monitor(*e), out);
        }
    }

    fn send_event(&mut self, counter: u16, event: LinkEvent, out: &mut impl FnMut(&[u8])) {
        let c = self.tx.event;
        self.tx.event = c.wrapping_add(1);
        send(&Message::Event(Tagged { counter, event }), c, out);
    }

    fn send_status(&mut self, out: &mut impl FnMut(&[u8])) {
        self.since_status = 0;
        let c = self.tx.status;
        self.tx.status = c.wrapping_add(1);
        send(&Message::Status(self.status()), c, out);
    }

    fn send_summary(&mut self, out: &mut impl FnMut(&[u8])) {
        let c = self.tx.summary;
        self.tx.summary = c.wrapping_add(1);
        let s = LinkSummary {
            counts: self.counts,
            ..self.summary
        };
        send(&Message::Summary(s), c, out);
    }
}

fn send(message: &Message, counter: u16, out: &mut impl FnMut(&[u8])) {
    let mut buf = [0u8; MAX_ENCODED];
    let n = payload::encode(message, counter, &mut buf);
    out(&buf[..n]);
}
