//! # link-checker
//!
//! The platform-independent half of the SDS link checker on a safety controller: everything
//! here is generic over a UART (`embedded_hal_nb::serial::{Read, Write}`), an
//! [`embedded_hal::digital::OutputPin`] and the caller's clock, so it runs unchanged on any
//! Cortex-M board (and is unit-tested on the host). `src/main.rs` is the QEMU board support
//! (MPS2-AN386: CMSDK UART0, an FPGA LED as the pin, SysTick as the clock).
//!
//! ```text
//!  UART rx ──> LinkTask::poll ──> monitor_core::link::Checker ──> Monitor
//!                    │                   │ (check status, window, segments)
//!  UART tx <─────────┼─── event / status / summary messages
//!                    └──> link_fault pin: high while the link is INVALID
//! ```
//!
//! The messages, the checks and what an integrator must provide are in the project's
//! docs/SCORE.md, "The monitor on a live link"; the measured figures in docs/FIRMWARE.md.
#![cfg_attr(not(test), no_std)]
#![deny(missing_docs)]
#![forbid(unsafe_code)]

use embedded_hal::digital::{Error as _, ErrorKind, OutputPin};
use embedded_hal_nb::{nb, serial};
use monitor_core::link::{Checker, LinkConfig, LinkConfigError, MAX_ENCODED};

/// Times a byte's write to a full transmit register is retried before the byte is given up
/// (counted in [`LinkTask::tx_dropped`]). A UART drains a byte in ten bit times (87 µs at
/// 115,200 baud: a few thousand polls at most), so the bound is never reached on a working
/// line; it only keeps a stuck transmitter, or a doer that stopped reading, from hanging the
/// checker. A lost status or summary is asked for again by the doer (it repeats a start or an
/// end until answered); a hung checker would miss its own timeout.
pub const TX_SPINS: u32 = 100_000;

/// Why the task stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TaskError {
    /// The link settings were refused.
    Config(LinkConfigError),
    /// The `link_fault` pin could not be driven: the checker cannot signal, the board must treat
    /// that as a fault of its own (reset, or the safe state).
    Pin(ErrorKind),
}

/// What the `link_fault` pin did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PinState {
    /// High now (the link is `INVALID`).
    pub high: bool,
    /// Times it went high.
    pub rises: u32,
}

/// The checker's task: one [`Checker`], the UART it listens and answers on, the `link_fault`
/// pin.
///
/// Call [`LinkTask::poll`] in the main loop (or from the UART's receive interrupt and a timer
/// set to [`LinkTask::deadline`]) with the board's monotonic clock in microseconds.
///
/// ```
/// use core::convert::Infallible;
/// use embedded_hal_nb::{nb, serial::{ErrorType, Read, Write}};
/// use link_checker::LinkTask;
/// use monitor_core::link::{self, LinkConfig, Message};
///
/// // A loop-back stand-in for a UART: bytes in from a buffer, answers out into one.
/// struct Wire { rx: Vec<u8>, tx: Vec<u8> }
/// impl ErrorType for Wire { type Error = Infallible; }
/// impl Read<u8> for Wire {
///     fn read(&mut self) -> nb::Result<u8, Infallible> {
///         if self.rx.is_empty() { Err(nb::Error::WouldBlock) } else { Ok(self.rx.remove(0)) }
///     }
/// }
/// impl Write<u8> for Wire {
///     fn write(&mut self, b: u8) -> nb::Result<(), Infallible> { self.tx.push(b); Ok(()) }
///     fn flush(&mut self) -> nb::Result<(), Infallible> { Ok(()) }
/// }
/// struct Pin;
/// impl embedded_hal::digital::ErrorType for Pin { type Error = Infallible; }
/// impl embedded_hal::digital::OutputPin for Pin {
///     fn set_low(&mut self) -> Result<(), Infallible> { Ok(()) }
///     fn set_high(&mut self) -> Result<(), Infallible> { Ok(()) }
/// }
///
/// let mut buf = [0u8; link::MAX_ENCODED];
/// let n = link::encode(&Message::Start(monitor_core::Config::DEFAULT), 0, &mut buf);
/// let wire = Wire { rx: buf[..n].to_vec(), tx: Vec::new() };
/// let mut task: LinkTask<_, _> = LinkTask::new(LinkConfig::DEFAULT, wire, Pin).unwrap();
/// while task.poll(0).unwrap() > 0 {}
/// let (wire, _) = task.release();
/// // The start is answered with a status message.
/// let mut rx = link::Deframer::new();
/// let answer = wire.tx.iter().find_map(|&b| rx.push(b).and_then(|m| m.ok().map(|m| link::decode(m))));
/// assert!(matches!(answer, Some(Ok((_, Message::Status(_))))));
/// ```
pub struct LinkTask<U, P, const N: usize = { monitor_core::DEFAULT_CAPACITY }> {
    checker: Checker<N>,
    uart: U,
    pin: P,
    pin_state: PinState,
    messages: u32,
    rx_errors: u32,
    tx_dropped: u32,
}

impl<U, P, const N: usize> LinkTask<U, P, N>
where
    U: serial::Read<u8> + serial::Write<u8>,
    P: OutputPin,
{
    /// A checker with the settings `link` (they must match the doer's); the pin is driven low.
    ///
    /// # Errors
    /// [`TaskError::Config`] for refused settings, [`TaskError::Pin`].
    pub fn new(link: LinkConfig, uart: U, mut pin: P) -> Result<Self, TaskError> {
        let checker = Checker::new(link).map_err(TaskError::Config)?;
        pin.set_low().map_err(|e| TaskError::Pin(e.kind()))?;
        Ok(LinkTask {
            checker,
            uart,
            pin,
            pin_state: PinState::default(),
            messages: 0,
            rx_errors: 0,
            tx_dropped: 0,
        })
    }

    /// Takes the bytes the UART holds, up to the end of one message (a 0x00) or
    /// [`MAX_ENCODED`] bytes, whichever comes first, answering on the UART; then checks the
    /// timeout at `now_us` and drives the pin. Returns the bytes taken (0: the UART had none).
    ///
    /// One message per call keeps the clock fresh and the timeout checked even under a flood
    /// of bytes: a doer that sends faster than the checker reads cannot starve it.
    ///
    /// # Errors
    /// [`TaskError::Pin`]. A receive error (overrun, framing) only counts in
    /// [`LinkTask::rx_errors`]: the byte it cost fails its message's check.
    pub fn poll(&mut self, now_us: u64) -> Result<usize, TaskError> {
        let LinkTask {
            checker,
            uart,
            tx_dropped,
            ..
        } = self;
        let mut taken = 0;
        while taken < MAX_ENCODED {
            match uart.read() {
                Ok(byte) => {
                    taken += 1;
                    checker.receive_byte(byte, now_us, &mut |bytes: &[u8]| {
                        send(uart, bytes, tx_dropped)
                    });
                    if byte == 0 {
                        self.messages = self.messages.wrapping_add(1);
                        break;
                    }
                }
                Err(nb::Error::WouldBlock) => break,
                Err(nb::Error::Other(_)) => {
                    self.rx_errors = self.rx_errors.saturating_add(1);
                }
            }
        }
        checker.poll(now_us, &mut |bytes: &[u8]| send(uart, bytes, tx_dropped));
        self.drive_pin()?;
        Ok(taken)
    }

    /// When [`LinkTask::poll`] must run at the latest for the timeout to be on time (the
    /// checker's deadline, µs; `None` while no timeout runs).
    pub fn deadline(&self) -> Option<u64> {
        self.checker.deadline()
    }

    /// The UART (a board's measurement modes steer a stand-in through it).
    pub fn uart_mut(&mut self) -> &mut U {
        &mut self.uart
    }

    /// The checker (its status, its settings).
    pub fn checker(&self) -> &Checker<N> {
        &self.checker
    }

    /// What the `link_fault` pin did.
    pub fn pin(&self) -> PinState {
        self.pin_state
    }

    /// Message ends (0x00 delimiters) received.
    pub fn messages(&self) -> u32 {
        self.messages
    }

    /// Receive errors the UART reported.
    pub fn rx_errors(&self) -> u32 {
        self.rx_errors
    }

    /// Answer bytes given up because the transmitter stayed full ([`TX_SPINS`]).
    pub fn tx_dropped(&self) -> u32 {
        self.tx_dropped
    }

    /// Gives the UART and the pin back.
    pub fn release(self) -> (U, P) {
        (self.uart, self.pin)
    }

    fn drive_pin(&mut self) -> Result<(), TaskError> {
        let high = !self.checker.link_valid();
        if high == self.pin_state.high {
            return Ok(());
        }
        if high {
            self.pin.set_high()
        } else {
            self.pin.set_low()
        }
        .map_err(|e| TaskError::Pin(e.kind()))?;
        if high {
            self.pin_state.rises = self.pin_state.rises.saturating_add(1);
        }
        self.pin_state.high = high;
        Ok(())
    }
}

/// Writes `bytes` on `uart`, waiting while the transmitter is full (at most [`TX_SPINS`] tries
/// per byte); a byte that cannot go, or that the UART refuses, counts in `dropped`.
fn send<U: serial::Write<u8>>(uart: &mut U, bytes: &[u8], dropped: &mut u32) {
    for &b in bytes {
        let mut spins = 0;
        loop {
            match uart.write(b) {
                Ok(()) => break,
                Err(nb::Error::WouldBlock) if spins < TX_SPINS => spins += 1,
                Err(_) => {
                    *dropped = dropped.saturating_add(1);
                    break;
                }
            }
        }
    }
}

/// A monotonic microsecond clock from a 24-bit down-counter (SysTick with its largest reload):
/// [`Ticks::now_us`] must be called at least once per counter period (0.67 s at 25 MHz) for
/// no wrap to be missed; the task's main loop calls it on every turn.
#[derive(Clone, Copy, Debug)]
pub struct Ticks {
    last: u32,
    ticks: u64,
    per_us: u32,
}

impl Ticks {
    /// A clock whose counter reads `now` and runs at `per_us` ticks per microsecond (at least 1).
    pub const fn new(now: u32, per_us: u32) -> Self {
        Ticks {
            last: now & 0x00FF_FFFF,
            ticks: 0,
            per_us: if per_us == 0 { 1 } else { per_us },
        }
    }

    /// Microseconds since [`Ticks::new`], given the counter's value `now`.
    ///
    /// ```
    /// let mut t = link_checker::Ticks::new(100, 25);
    /// assert_eq!(t.now_us(50), 2);              // 50 ticks down
    /// assert_eq!(t.now_us(0x00FF_FFFF - 49), 6); // wrapped: 100 more, 150 in all
    /// ```
    pub fn now_us(&mut self, now: u32) -> u64 {
        let now = now & 0x00FF_FFFF;
        // A down-counter modulo 2^24.
        let elapsed = self.last.wrapping_sub(now) & 0x00FF_FFFF;
        self.last = now;
        self.ticks = self.ticks.wrapping_add(u64::from(elapsed));
        self.ticks / u64::from(self.per_us)
    }
}

/// Writes `n` in decimal into `buf`; returns the digits (no formatting machinery).
///
/// ```
/// let mut d = [0u8; 10];
/// assert_eq!(link_checker::decimal(4_294_967_295, &mut d), b"4294967295");
/// ```
pub fn decimal(mut n: u32, buf: &mut [u8; 10]) -> &[u8] {
    let mut len = 0;
    for slot in buf.iter_mut().rev() {
        *slot = b'0' + (n % 10) as u8;
        n /= 10;
        len += 1;
        if n == 0 {
            break;
        }
    }
    buf.get(10 - len..).unwrap_or(&[])
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::convert::Infallible;
    use monitor_core::link::{self, CheckStatus, Deframer, LinkEvent, Message, RouteState};
    use monitor_core::{Config, Frame};
    use std::collections::VecDeque;
    use std::vec::Vec;

    /// A UART over two buffers; `tx_full` makes every write block.
    #[derive(Default)]
    struct Wire {
        rx: VecDeque<u8>,
        tx: Vec<u8>,
        tx_full: bool,
        overrun_at: Option<usize>,
        read: usize,
    }

    #[derive(Debug)]
    struct Overrun;
    impl serial::Error for Overrun {
        fn kind(&self) -> serial::ErrorKind {
            serial::ErrorKind::Overrun
        }
    }
    impl serial::ErrorType for Wire {
        type Error = Overrun;
    }
    impl serial::Read<u8> for Wire {
        fn read(&mut self) -> nb::Result<u8, Overrun> {
            if self.overrun_at == Some(self.read) {
                self.overrun_at = None;
                return Err(nb::Error::Other(Overrun));
            }
            let b = self.rx.pop_front().ok_or(nb::Error::WouldBlock)?;
            self.read += 1;
            Ok(b)
        }
    }
    impl serial::Write<u8> for Wire {
        fn write(&mut self, b: u8) -> nb::Result<(), Overrun> {
            if self.tx_full {
                return Err(nb::Error::WouldBlock);
            }
            self.tx.push(b);
            Ok(())
        }
        fn flush(&mut self) -> nb::Result<(), Overrun> {
            Ok(())
        }
    }

    /// A pin that remembers its level and its writes.
    #[derive(Default)]
    struct Pin {
        high: bool,
        writes: u32,
    }
    impl embedded_hal::digital::ErrorType for Pin {
        type Error = Infallible;
    }
    impl OutputPin for Pin {
        fn set_low(&mut self) -> Result<(), Infallible> {
            self.high = false;
            self.writes += 1;
            Ok(())
        }
        fn set_high(&mut self) -> Result<(), Infallible> {
            self.high = true;
            self.writes += 1;
            Ok(())
        }
    }

    fn put(wire: &mut Vec<u8>, m: &Message, counter: u16) {
        let mut buf = [0u8; link::MAX_ENCODED];
        let n = link::encode(m, counter, &mut buf);
        wire.extend_from_slice(&buf[..n]);
    }

    fn answers(tx: &[u8]) -> Vec<Message> {
        let mut rx = Deframer::new();
        tx.iter()
            .filter_map(|&b| rx.push(b).and_then(|m| m.ok().map(|m| link::decode(m))))
            .map(|r| r.expect("the checker's answers pass their own check").1)
            .collect()
    }

    fn drain(task: &mut LinkTask<Wire, Pin>, now_us: u64) {
        while task.poll(now_us).unwrap() > 0 {}
    }

    fn cruise() -> Frame {
        Frame {
            speed: 8.0,
            lat_err: Some(0.1),
            ..Frame::default()
        }
    }

    #[test]
    fn a_clean_route_is_answered_and_the_pin_stays_low() {
        let mut bytes = Vec::new();
        put(&mut bytes, &Message::Start(Config::DEFAULT), 0);
        for c in 0..40 {
            put(&mut bytes, &Message::Frame(cruise()), c);
        }
        put(&mut bytes, &Message::End { frames: 40 }, 0);
        let wire = Wire {
            rx: bytes.into(),
            ..Wire::default()
        };
        let mut task = LinkTask::new(LinkConfig::DEFAULT, wire, Pin::default()).unwrap();
        drain(&mut task, 0);
        assert_eq!(task.messages(), 42);
        assert_eq!(task.checker().status().route, RouteState::Finished);
        assert_eq!(task.pin(), PinState::default());
        let (wire, pin) = task.release();
        assert!(!pin.high);
        let msgs = answers(&wire.tx);
        let Some(Message::Summary(s)) = msgs.last() else {
            panic!("no summary last: {msgs:?}");
        };
        assert_eq!((s.route.frames, s.segments), (40, 1));
        assert_eq!(s.counts.get(CheckStatus::Ok), 40);
    }

    #[test]
    fn garbage_raises_the_pin_and_clean_frames_lower_it() {
        let mut bytes = Vec::new();
        put(&mut bytes, &Message::Start(Config::DEFAULT), 0);
        for c in 0..5 {
            put(&mut bytes, &Message::Frame(cruise()), c);
        }
        // Three messages of random bytes: three ERRORs in the window (max 2) → INVALID.
        bytes.extend_from_slice(&[7, 1, 2, 3, 0, 9, 9, 0, 0x42, 0x13, 0x37, 0]);
        let wire = Wire {
            rx: bytes.into(),
            ..Wire::default()
        };
        let mut task = LinkTask::new(LinkConfig::DEFAULT, wire, Pin::default()).unwrap();
        drain(&mut task, 0);
        assert_eq!(
            task.pin(),
            PinState {
                high: true,
                rises: 1
            }
        );
        assert!(task.pin.high);
        // 20 clean frames push the errors out of the window: VALID again, the pin low.
        let mut more = Vec::new();
        for c in 5..25 {
            put(&mut more, &Message::Frame(cruise()), c);
        }
        task.uart.rx.extend(more);
        drain(&mut task, 0);
        assert_eq!(
            task.pin(),
            PinState {
                high: false,
                rises: 1
            }
        );
        let (wire, pin) = task.release();
        assert!(!pin.high);
        assert_eq!(
            pin.writes, 3,
            "low at start, high once, low once: no write without a change"
        );
        let events: Vec<LinkEvent> = answers(&wire.tx)
            .into_iter()
            .filter_map(|m| match m {
                Message::Event(t) => Some(t.event),
                _ => None,
            })
            .filter(|e| !matches!(e, LinkEvent::Monitor(_) | LinkEvent::Segment { .. }))
            .collect();
        assert_eq!(
            events,
            [
                LinkEvent::LinkFault { bad: 3 },
                LinkEvent::LinkRestored { bad: 2 }
            ]
        );
    }

    #[test]
    fn one_message_per_poll_even_under_a_flood() {
        let mut bytes = Vec::new();
        for c in 0..3 {
            put(&mut bytes, &Message::Frame(cruise()), c);
        }
        let one = bytes.len() / 3;
        // A doer gone mad: bytes without any delimiter.
        bytes.extend(core::iter::repeat_n(0x55, 3 * MAX_ENCODED));
        let wire = Wire {
            rx: bytes.into(),
            ..Wire::default()
        };
        let mut task = LinkTask::new(LinkConfig::DEFAULT, wire, Pin::default()).unwrap();
        assert_eq!(task.poll(0).unwrap(), one);
        assert_eq!(task.messages(), 1);
        drain(&mut task, 0);
        assert_eq!(task.messages(), 3);
        // The flood was taken MAX_ENCODED bytes at a time, each call checking the timeout.
        assert!(task.uart.rx.is_empty());
    }

    #[test]
    fn a_stuck_transmitter_costs_answers_not_the_checker() {
        let mut bytes = Vec::new();
        put(&mut bytes, &Message::Start(Config::DEFAULT), 0);
        put(&mut bytes, &Message::Frame(cruise()), 0);
        let wire = Wire {
            rx: bytes.into(),
            tx_full: true,
            ..Wire::default()
        };
        let mut task = LinkTask::new(LinkConfig::DEFAULT, wire, Pin::default()).unwrap();
        drain(&mut task, 0);
        assert_eq!(task.messages(), 2);
        assert_eq!(task.checker().status().accepted, 1);
        // The status answering the start, and the segment event of the first frame, were lost.
        assert!(task.tx_dropped() > 40, "{}", task.tx_dropped());
    }

    #[test]
    fn a_receive_error_is_counted_and_its_message_fails_its_check() {
        let mut bytes = Vec::new();
        put(&mut bytes, &Message::Start(Config::DEFAULT), 0);
        let start = bytes.len();
        put(&mut bytes, &Message::Frame(cruise()), 0);
        put(&mut bytes, &Message::Frame(cruise()), 1);
        // The overrun loses the frame's 10th byte.
        let lost = start + 10;
        bytes.remove(lost);
        let wire = Wire {
            rx: bytes.into(),
            overrun_at: Some(lost),
            ..Wire::default()
        };
        let mut task = LinkTask::new(LinkConfig::DEFAULT, wire, Pin::default()).unwrap();
        drain(&mut task, 0);
        assert_eq!(task.rx_errors(), 1);
        let s = task.checker().status();
        assert_eq!(
            (
                s.counts.get(CheckStatus::Error),
                s.counts.get(CheckStatus::Ok),
                s.accepted
            ),
            (1, 1, 1)
        );
    }

    #[test]
    fn the_timeout_is_checked_by_poll_without_bytes() {
        let mut bytes = Vec::new();
        put(&mut bytes, &Message::Start(Config::DEFAULT), 0);
        put(&mut bytes, &Message::Frame(cruise()), 0);
        let wire = Wire {
            rx: bytes.into(),
            ..Wire::default()
        };
        let mut task = LinkTask::new(LinkConfig::DEFAULT, wire, Pin::default()).unwrap();
        drain(&mut task, 1_000);
        let deadline = task.deadline().unwrap();
        assert_eq!(deadline, 1_000 + 150_000, "3 periods of 50 ms");
        assert_eq!(task.poll(deadline - 1).unwrap(), 0);
        assert_eq!(
            task.checker().status().counts.get(CheckStatus::NoNewData),
            0
        );
        assert_eq!(task.poll(deadline).unwrap(), 0);
        assert_eq!(
            task.checker().status().counts.get(CheckStatus::NoNewData),
            1
        );
    }

    #[test]
    fn the_clock_extends_the_24_bit_counter() {
        let mut t = Ticks::new(0, 25);
        // 0 → wraps to 0xFF_FFFF after one tick.
        assert_eq!(t.now_us(0x00FF_FFFF), 0);
        let mut us = 0;
        for _ in 0..10 {
            // Half a period each time, ten times: five periods.
            let now = t.last.wrapping_sub(1 << 23) & 0x00FF_FFFF;
            us = t.now_us(now);
        }
        assert_eq!(us, (1 + 10 * (1u64 << 23)) / 25);
        // The upper byte of a register read is ignored.
        assert_eq!(Ticks::new(0xFF00_0010, 1).now_us(0xAB00_0000), 16);
    }
}
