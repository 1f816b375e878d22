//! # firmware-example
//!
//! The platform-independent half of the vehicle-side SDS monitor: everything here is generic
//! over [`embedded_hal::digital::OutputPin`] and a [`FrameSource`], so it runs unchanged on any
//! Cortex-M board (and is unit-tested on the host). `src/main.rs` is the QEMU board support:
//! semihosting output, the frame table in flash, the measurement modes.
//!
//! ```text
//! FrameSource ──> MonitorTask::poll ──> monitor_core::Monitor::push ──> Events
//!                        │                                               │
//!                        └── alarm pin: collision without deceleration,  │
//!                            or a critical lateral chunk (latched)  <────┤
//!                        └── comfort pin: the last chunk failed a   <────┘
//!                            comfort bound
//! ```
#![no_std]
#![deny(missing_docs)]
#![forbid(unsafe_code)]

pub mod table;

use embedded_hal::digital::{Error as _, ErrorKind, OutputPin};
use monitor_core::{Band, Event, Events, Finished, Frame, Monitor, MonitorError};

/// Where frames come from: a recorded route in flash here; on a vehicle, the telemetry feed
/// (CAN, UART, shared memory...). `Ok(None)` ends the route.
pub trait FrameSource {
    /// Why a frame could not be read.
    type Error;
    /// The next frame, or `None` at the end of the route.
    fn next_frame(&mut self) -> Result<Option<Frame>, Self::Error>;
}

/// Why the frame table cannot be read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TableError {
    /// Not a version-1 table, or its length disagrees with its frame count.
    BadTable,
}

/// The recorded routes: the compact table of [`table`], typically `include_bytes!`'d into flash.
#[derive(Clone, Debug)]
pub struct FlashRoutes<'a> {
    rest: &'a [u8],
    routes: u16,
    frames: u32,
}

impl<'a> FlashRoutes<'a> {
    /// Checks the header and that the routes fill the table exactly.
    pub fn new(bytes: &'a [u8]) -> Result<Self, TableError> {
        let (header, rest) = bytes
            .split_first_chunk::<{ table::HEADER_LEN }>()
            .ok_or(TableError::BadTable)?;
        let (routes, frames) = table::parse_header(header).ok_or(TableError::BadTable)?;
        let all = FlashRoutes {
            rest,
            routes,
            frames,
        };
        let mut walk = all.clone();
        let mut seen: u32 = 0;
        for _ in 0..routes {
            let route = walk.next_route().ok_or(TableError::BadTable)?;
            if route.count() == 0 {
                return Err(TableError::BadTable); // build.rs never writes an empty route
            }
            seen = seen
                .checked_add(route.count())
                .ok_or(TableError::BadTable)?;
        }
        if !walk.rest.is_empty() || seen != frames {
            return Err(TableError::BadTable);
        }
        Ok(all)
    }

    /// Routes in the table.
    pub fn routes(&self) -> u16 {
        self.routes
    }

    /// Frames in all routes.
    pub fn frames(&self) -> u32 {
        self.frames
    }

    /// The next route, or `None` after the last one.
    pub fn next_route(&mut self) -> Option<FlashFrames<'a>> {
        let (count, rest) = self.rest.split_first_chunk::<4>()?;
        let count = u32::from_le_bytes(*count);
        let len = (count as usize).checked_mul(table::RECORD_LEN)?;
        let records = rest.get(..len)?;
        self.rest = rest.get(len..)?;
        Some(FlashFrames { records, count })
    }
}

/// One recorded route: a [`FrameSource`] over its records.
#[derive(Clone, Debug)]
pub struct FlashFrames<'a> {
    records: &'a [u8],
    count: u32,
}

impl FlashFrames<'_> {
    /// Frames in the route.
    pub fn count(&self) -> u32 {
        self.count
    }

    /// Frames not read yet.
    pub fn remaining(&self) -> usize {
        self.records.len() / table::RECORD_LEN
    }
}

impl FrameSource for FlashFrames<'_> {
    type Error = TableError;

    fn next_frame(&mut self) -> Result<Option<Frame>, TableError> {
        match self.records.split_first_chunk::<{ table::RECORD_LEN }>() {
            Some((record, rest)) => {
                self.records = rest;
                Ok(Some(table::decode_record(record)))
            }
            None => Ok(None),
        }
    }
}

/// Why the monitor task stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TaskError<E> {
    /// The frame source failed.
    Source(E),
    /// The monitor rejected a frame (non-finite, negative speed...) or the route was finished.
    Monitor(MonitorError),
    /// The alarm pin could not be driven.
    AlarmPin(ErrorKind),
    /// The comfort pin could not be driven.
    ComfortPin(ErrorKind),
}

/// What the pins did over the route (for the log and the host comparison).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PinState {
    /// Alarm pin level now.
    pub alarm: bool,
    /// Times the alarm pin went high.
    pub alarm_rises: u32,
    /// Comfort pin level now.
    pub comfort: bool,
    /// Times the comfort pin went high.
    pub comfort_rises: u32,
}

impl PinState {
    /// Applies one event with the task's rules; returns whether (alarm, comfort) must be driven,
    /// and to which level. The alarm latches high on a collision without deceleration or a
    /// critical lateral chunk; the comfort pin shows the last comfort verdict (high = failed).
    pub fn apply(&mut self, event: &Event) -> (Option<bool>, Option<bool>) {
        match event {
            Event::Collision(v) if v.nodecel() => (Some(self.set_alarm()), None),
            Event::Lateral(v) if v.band == Band::Critical => (Some(self.set_alarm()), None),
            Event::Comfort(v) => {
                let failed = !v.failed.comfortable();
                if failed && !self.comfort {
                    self.comfort_rises = self.comfort_rises.saturating_add(1);
                }
                self.comfort = failed;
                (None, Some(failed))
            }
            _ => (None, None),
        }
    }

    fn set_alarm(&mut self) -> bool {
        if !self.alarm {
            self.alarm_rises = self.alarm_rises.saturating_add(1);
        }
        self.alarm = true;
        true
    }
}

/// The vehicle-side monitor task: one [`Monitor`] and two output pins.
///
/// * `alarm` goes high on a collision without prior deceleration or on a critical lateral chunk,
///   and stays high until [`MonitorTask::acknowledge`];
/// * `comfort` is high while the last scored chunk failed a comfort bound.
pub struct MonitorTask<A, C> {
    monitor: Monitor,
    alarm: A,
    comfort: C,
    pins: PinState,
}

impl<A: OutputPin, C: OutputPin> MonitorTask<A, C> {
    /// A task with the default configuration (`Config::DEFAULT`); both pins are driven low.
    pub fn new(mut alarm: A, mut comfort: C) -> Result<Self, TaskError<core::convert::Infallible>> {
        alarm.set_low().map_err(|e| TaskError::AlarmPin(e.kind()))?;
        comfort
            .set_low()
            .map_err(|e| TaskError::ComfortPin(e.kind()))?;
        Ok(MonitorTask {
            monitor: Monitor::default(),
            alarm,
            comfort,
            pins: PinState::default(),
        })
    }

    /// Reads one frame from `source`, pushes it, drives the pins and hands each event to
    /// `on_event`. `Ok(false)` at the end of the route (then call [`MonitorTask::finish`]).
    ///
    /// Events are lent to the callback rather than returned: moving the 64-byte event list
    /// through `Result`/`Option` layers cost ~1,000 instructions per frame on Cortex-M4.
    pub fn poll<S: FrameSource>(
        &mut self,
        source: &mut S,
        mut on_event: impl FnMut(&Event),
    ) -> Result<bool, TaskError<S::Error>> {
        let frame = match source.next_frame() {
            Ok(Some(frame)) => frame,
            Ok(None) => return Ok(false),
            Err(e) => return Err(TaskError::Source(e)),
        };
        let events = match self.monitor.push(&frame) {
            Ok(events) => events,
            Err(e) => return Err(TaskError::Monitor(e)),
        };
        self.drive(&events)?;
        for e in &events {
            on_event(e);
        }
        Ok(true)
    }

    /// Ends the route: the last chunk's events (pins driven) and the summary.
    pub fn finish<E>(&mut self) -> Result<Finished, TaskError<E>> {
        let done = self.monitor.finish().map_err(TaskError::Monitor)?;
        self.drive(&done.events)?;
        Ok(done)
    }

    /// Starts a new route: a fresh monitor (same configuration), both pins low.
    pub fn reset<E>(&mut self) -> Result<(), TaskError<E>> {
        self.monitor.reset();
        self.pins = PinState::default();
        self.alarm
            .set_low()
            .map_err(|e| TaskError::AlarmPin(e.kind()))?;
        self.comfort
            .set_low()
            .map_err(|e| TaskError::ComfortPin(e.kind()))
    }

    /// Clears the latched alarm (an operator acknowledged it).
    pub fn acknowledge<E>(&mut self) -> Result<(), TaskError<E>> {
        self.pins.alarm = false;
        self.alarm
            .set_low()
            .map_err(|e| TaskError::AlarmPin(e.kind()))
    }

    /// What the pins did so far.
    pub fn pins(&self) -> PinState {
        self.pins
    }

    /// The monitor (its summary so far, its configuration).
    pub fn monitor(&self) -> &Monitor {
        &self.monitor
    }

    /// Gives the pins back.
    pub fn release(self) -> (A, C) {
        (self.alarm, self.comfort)
    }

    fn drive<E>(&mut self, events: &Events) -> Result<(), TaskError<E>> {
        for event in events {
            let (alarm, comfort) = self.pins.apply(event);
            if let Some(level) = alarm {
                set(&mut self.alarm, level).map_err(TaskError::AlarmPin)?;
            }
            if let Some(level) = comfort {
                set(&mut self.comfort, level).map_err(TaskError::ComfortPin)?;
            }
        }
        Ok(())
    }
}

fn set<P: OutputPin>(pin: &mut P, high: bool) -> Result<(), ErrorKind> {
    if high { pin.set_high() } else { pin.set_low() }.map_err(|e| e.kind())
}

/// Writes `n` in decimal into `buf`; returns the digits (no allocation, no formatting machinery).
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

/// Writes `pins {"alarm":..,"alarm_rises":..,"comfort":..,"comfort_rises":..}` (no newline) into
/// `out`; returns the length, or `None` when `out` is too small. The host replay prints the same.
pub fn pins_line(p: &PinState, out: &mut [u8]) -> Option<usize> {
    let mut w = Writer { out, len: 0 };
    let mut d = [0u8; 10];
    let flag = |b: bool| if b { &b"true"[..] } else { &b"false"[..] };
    w.put(b"pins {\"alarm\":")?;
    w.put(flag(p.alarm))?;
    w.put(b",\"alarm_rises\":")?;
    w.put(decimal(p.alarm_rises, &mut d))?;
    w.put(b",\"comfort\":")?;
    w.put(flag(p.comfort))?;
    w.put(b",\"comfort_rises\":")?;
    w.put(decimal(p.comfort_rises, &mut d))?;
    w.put(b"}")?;
    Some(w.len)
}

/// Appends bytes to a fixed buffer without panicking.
pub struct Writer<'a> {
    /// The buffer.
    pub out: &'a mut [u8],
    /// Bytes written.
    pub len: usize,
}

impl Writer<'_> {
    /// Appends `bytes`; `None` (nothing written) when they do not fit.
    pub fn put(&mut self, bytes: &[u8]) -> Option<()> {
        let end = self.len.checked_add(bytes.len())?;
        self.out.get_mut(self.len..end)?.copy_from_slice(bytes);
        self.len = end;
        Some(())
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use core::convert::Infallible;
    use monitor_core::Collisions;

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

    fn table_of(routes: &[&[Frame]]) -> std::vec::Vec<u8> {
        let total: usize = routes.iter().map(|r| r.len()).sum();
        let mut t = table::header(routes.len() as u16, total as u32).to_vec();
        for r in routes {
            t.extend_from_slice(&(r.len() as u32).to_le_bytes());
            for f in r.iter() {
                t.extend_from_slice(&table::encode_record(f));
            }
        }
        t
    }

    #[test]
    fn records_round_trip_bit_for_bit() {
        let f = Frame {
            a_lon: -0.0,
            a_lat: f32::from_bits(1), // a subnormal
            a_mag: 3.4e38,
            yaw_rate: -12.345_678,
            speed: 7.25,
            lat_err: Some(0.0),
            collisions: Collisions {
                pedestrian: 1,
                vehicle: 65535,
                layout: 3,
                workzone: 2,
            },
        };
        let g = table::decode_record(&table::encode_record(&f));
        assert_eq!(g.a_lon.to_bits(), f.a_lon.to_bits());
        assert_eq!(g.a_lat.to_bits(), 1);
        assert_eq!(g, f);
        let unknown = Frame { lat_err: None, ..f };
        assert_eq!(
            table::decode_record(&table::encode_record(&unknown)).lat_err,
            None
        );
    }

    #[test]
    fn flash_frames_reads_every_frame_then_ends() {
        let frames = [
            Frame::default(),
            Frame {
                speed: 3.0,
                ..Frame::default()
            },
        ];
        let third = [Frame {
            a_lon: -1.0,
            ..Frame::default()
        }];
        let bytes = table_of(&[&frames, &third]);
        let mut routes = FlashRoutes::new(&bytes).unwrap();
        assert_eq!((routes.routes(), routes.frames()), (2, 3));
        let mut src = routes.next_route().unwrap();
        assert_eq!(src.count(), 2);
        assert_eq!(src.next_frame(), Ok(Some(frames[0])));
        assert_eq!(src.next_frame(), Ok(Some(frames[1])));
        assert_eq!(src.next_frame(), Ok(None));
        let mut src = routes.next_route().unwrap();
        assert_eq!(src.next_frame(), Ok(Some(third[0])));
        assert_eq!(src.next_frame(), Ok(None));
        assert!(routes.next_route().is_none());
    }

    #[test]
    fn flash_frames_rejects_bad_tables() {
        let bytes = table_of(&[&[Frame::default()], &[Frame::default()]]);
        assert!(FlashRoutes::new(&bytes).is_ok());
        assert!(FlashRoutes::new(&bytes[..bytes.len() - 1]).is_err());
        assert!(FlashRoutes::new(&bytes[..5]).is_err());
        let mut extra = bytes.clone();
        extra.push(0);
        assert!(FlashRoutes::new(&extra).is_err());
        let mut wrong_total = bytes.clone();
        wrong_total[8] = 3;
        assert!(FlashRoutes::new(&wrong_total).is_err());
        let mut wrong_routes = bytes.clone();
        wrong_routes[6] = 3;
        assert!(FlashRoutes::new(&wrong_routes).is_err());
        for n in [0, 2, 3] {
            let mut wrong_route_len = bytes.clone();
            wrong_route_len[12] = n;
            assert!(
                FlashRoutes::new(&wrong_route_len).is_err(),
                "route of {n} frames"
            );
        }
        let mut magic = bytes;
        magic[0] = b'X';
        assert!(FlashRoutes::new(&magic).is_err());
    }

    #[test]
    fn alarm_latches_on_nodecel_collision_and_comfort_follows_chunks() {
        let cruise = Frame {
            speed: 10.0,
            lat_err: Some(0.1),
            ..Frame::default()
        };
        let mut frames = std::vec![cruise; 25];
        frames.push(Frame {
            collisions: Collisions {
                vehicle: 1,
                ..Collisions::NONE
            },
            ..cruise
        });
        let bytes = table_of(&[&frames]);
        let mut src = FlashRoutes::new(&bytes).unwrap().next_route().unwrap();
        let mut task = MonitorTask::new(Pin::default(), Pin::default()).unwrap();
        let mut n = 0;
        while task.poll(&mut src, |_| ()).unwrap() {
            n += 1;
            // Chunk 0 (frames 0..20) is comfortable; the hit is at frame 25.
            assert_eq!(task.pins().alarm, n == 26);
        }
        assert_eq!(n, 26);
        let done = task.finish::<TableError>().unwrap();
        assert_eq!(done.summary.collisions.nodecel, 1);
        let p = task.pins();
        assert_eq!(
            (p.alarm, p.alarm_rises, p.comfort, p.comfort_rises),
            (true, 1, false, 0)
        );
        task.acknowledge::<TableError>().unwrap();
        assert!(!task.pins().alarm);
        task.reset::<TableError>().unwrap();
        assert_eq!(task.monitor().frames(), 0);
        assert_eq!(task.pins(), PinState::default());
        let (alarm, comfort) = task.release();
        assert!(!alarm.high);
        assert!(!comfort.high);
    }

    #[test]
    fn comfort_pin_goes_high_on_a_failed_chunk_and_low_again() {
        let mut p = PinState::default();
        let failed = monitor_core::ComfortVerdict {
            chunk: 0,
            frames: 20,
            failed: monitor_core::Failures {
                lon_jerk: true,
                ..Default::default()
            },
        };
        let ok = monitor_core::ComfortVerdict {
            failed: Default::default(),
            ..failed
        };
        assert_eq!(p.apply(&Event::Comfort(failed)), (None, Some(true)));
        assert_eq!(p.apply(&Event::Comfort(failed)), (None, Some(true)));
        assert_eq!(p.apply(&Event::Comfort(ok)), (None, Some(false)));
        assert_eq!(p.apply(&Event::Comfort(failed)), (None, Some(true)));
        assert_eq!(p.comfort_rises, 2);
        assert!(!p.alarm);
    }

    #[test]
    fn pins_line_and_decimal() {
        let mut d = [0u8; 10];
        assert_eq!(decimal(0, &mut d), b"0");
        assert_eq!(decimal(u32::MAX, &mut d), b"4294967295");
        let mut out = [0u8; 128];
        let p = PinState {
            alarm: true,
            alarm_rises: 1,
            comfort: false,
            comfort_rises: 12,
        };
        let n = pins_line(&p, &mut out).unwrap();
        assert_eq!(
            &out[..n],
            br#"pins {"alarm":true,"alarm_rises":1,"comfort":false,"comfort_rises":12}"#
        );
        assert_eq!(pins_line(&p, &mut out[..20]), None);
    }
}
