//! The QEMU board support of the SDS monitor: replays the recorded route in flash through
//! [`MonitorTask`], prints every event and the summary over semihosting, and exits with the
//! firmware's own status (0 on success).
//!
//! Modes, from the semihosting command line (`-semihosting-config ...,arg=fw,arg=MODE`):
//! * `run` (default): for each route in flash, a `route I` line, then `event {json}`,
//!   `summary {json}` and `pins {json}` lines exactly as `monitor_replay` prints them on the host;
//!   then `stack`, `monitor_size`, `routes` lines and `done`;
//! * `bench N`: push the first N frames of the first route (pins driven, nothing printed) and exit: the
//!   instruction-count plugin's total for `bench N` minus `bench 0` is the monitor's share;
//! * `ticks`: push every frame of the first route and print `ticks FRAME T` for each, T being the SysTick count of
//!   the push; under `-icount shift=0` it advances with the instructions executed.
#![no_std]
#![no_main]

use core::convert::Infallible;

use cortex_m_rt::entry;
use cortex_m_semihosting::{debug, hio, nr};
use embedded_hal::digital::{ErrorType, OutputPin};
#[cfg(feature = "json-report")]
use firmware_example::Writer;
use firmware_example::{decimal, pins_line, FlashFrames, FlashRoutes, MonitorTask};
use monitor_core::MONITOR_SIZE;
#[cfg(feature = "json-report")]
use monitor_core::{json, Event};

include!(concat!(env!("OUT_DIR"), "/frames.rs"));

/// A GPIO stand-in for the QEMU boards: it keeps its level in RAM (volatile, so the writes are
/// not optimised away, as a GPIO register's would not be). On a real board, pass the HAL's pins.
struct RamPin {
    level: u32,
}

impl RamPin {
    const fn new() -> Self {
        RamPin { level: 0 }
    }
    fn write(&mut self, v: u32) {
        // SAFETY: a valid, aligned, exclusive reference.
        unsafe { core::ptr::write_volatile(&mut self.level, v) }
    }
}

impl ErrorType for RamPin {
    type Error = Infallible;
}

impl OutputPin for RamPin {
    fn set_low(&mut self) -> Result<(), Infallible> {
        self.write(0);
        Ok(())
    }
    fn set_high(&mut self) -> Result<(), Infallible> {
        self.write(1);
        Ok(())
    }
}

/// Semihosting stdout; remembers a failed write.
struct Console {
    out: Option<hio::HostStream>,
    failed: bool,
}

impl Console {
    fn open() -> Self {
        let out = hio::hstdout().ok();
        Console {
            failed: out.is_none(),
            out,
        }
    }
    fn write(&mut self, bytes: &[u8]) {
        match self.out.as_mut() {
            Some(out) => {
                if out.write_all(bytes).is_err() {
                    self.failed = true;
                }
            }
            None => self.failed = true,
        }
    }
    /// `prefix`, the JSON of `value`, a newline.
    #[cfg(feature = "json-report")]
    fn json<T: serde::Serialize>(&mut self, prefix: &[u8], value: &T) {
        let mut buf = [0u8; 640];
        let mut w = Writer {
            out: &mut buf,
            len: 0,
        };
        let ok = w.put(prefix).is_some()
            && match w.out.get_mut(w.len..) {
                Some(rest) => match json::encode(value, rest) {
                    Ok(n) => {
                        w.len += n;
                        w.put(b"\n").is_some()
                    }
                    Err(_) => false,
                },
                None => false,
            };
        if ok {
            let n = w.len;
            self.write(buf.get(..n).unwrap_or(&[]));
        } else {
            self.write(b"error: line buffer too small\n");
            self.failed = true;
        }
    }
    /// Text and numbers, in turn, then a newline.
    fn parts(&mut self, parts: &[(&[u8], u32)], tail: &[u8]) {
        for &(text, n) in parts {
            let mut d = [0u8; 10];
            self.write(text);
            self.write(decimal(n, &mut d));
        }
        self.write(tail);
        self.write(b"\n");
    }
}

enum Mode {
    Run,
    Bench(u32),
    Ticks,
}

/// The semihosting command line, parsed: the first word is the program name.
fn mode() -> Option<Mode> {
    let mut buf = [0u8; 96];
    let mut block: [usize; 2] = [buf.as_mut_ptr() as usize, buf.len()];
    // SAFETY: SYS_GET_CMDLINE writes at most block[1] bytes into buf and the length into block.
    let r = unsafe { cortex_m_semihosting::syscall1(nr::GET_CMDLINE, block.as_mut_ptr() as usize) };
    if r != 0 {
        return Some(Mode::Run); // no command line: the default mode
    }
    let line = buf.get(..block[1].min(buf.len())).unwrap_or(&[]);
    let mut words = line
        .split(|&b| b == b' ' || b == 0)
        .filter(|w| !w.is_empty());
    let _program = words.next();
    match words.next() {
        None | Some(b"run") => Some(Mode::Run),
        Some(b"ticks") => Some(Mode::Ticks),
        Some(b"bench") => {
            let digits = words.next()?;
            let mut n: u32 = 0;
            for &d in digits {
                if !d.is_ascii_digit() {
                    return None;
                }
                n = n.checked_mul(10)?.checked_add(u32::from(d - b'0'))?;
            }
            Some(Mode::Bench(n))
        }
        Some(_) => None,
    }
}

// SysTick (ARMv7-M architecture registers, the same on every Cortex-M3/M4).
const SYST_CSR: *mut u32 = 0xE000_E010 as *mut u32;
const SYST_RVR: *mut u32 = 0xE000_E014 as *mut u32;
const SYST_CVR: *mut u32 = 0xE000_E018 as *mut u32;

fn systick_start() {
    // SAFETY: architecturally defined SysTick registers; nothing else uses SysTick here.
    unsafe {
        core::ptr::write_volatile(SYST_RVR, 0x00FF_FFFF);
        core::ptr::write_volatile(SYST_CVR, 0);
        // Enable, processor clock, no interrupt.
        core::ptr::write_volatile(SYST_CSR, 0b101);
    }
}

fn systick_now() -> u32 {
    // SAFETY: reading the architecturally defined current-value register.
    unsafe { core::ptr::read_volatile(SYST_CVR) }
}

/// Bytes of the stack used so far: cortex-m-rt painted `_stack_end.._stack_start` with
/// 0xCCCC_CCCC before `main`; the lowest word that lost its paint is the high-water mark.
fn stack_used() -> (u32, u32) {
    extern "C" {
        static mut _stack_end: u32;
        static mut _stack_start: u32;
    }
    let end = &raw const _stack_end as usize;
    let start = &raw const _stack_start as usize;
    let mut p = end;
    while p < start {
        // SAFETY: [_stack_end, _stack_start) is RAM reserved for the stack, word aligned.
        let v = unsafe { core::ptr::read_volatile(p as *const u32) };
        if v != cortex_m_rt::STACK_PAINT_VALUE {
            break;
        }
        p += 4;
    }
    ((start - p) as u32, (start - end) as u32)
}

fn run(con: &mut Console) -> bool {
    let Some(mode) = mode() else {
        con.write(b"error: unknown mode (use run, bench N or ticks)\n");
        return false;
    };
    let Ok(mut routes) = FlashRoutes::new(&FRAME_TABLE) else {
        con.write(b"error: bad frame table\n");
        return false;
    };
    let Ok(mut task) = MonitorTask::new(RamPin::new(), RamPin::new()) else {
        return false;
    };
    // `bench` and `ticks` measure the first route.
    let Some(mut source) = routes.clone().next_route() else {
        return false;
    };
    let total = source.count();
    let routes_frames = routes.frames();

    match mode {
        Mode::Bench(n) => {
            #[cfg(feature = "panic-canary")]
            {
                // An index the optimiser cannot bound: its panic must stop the link.
                let table = [1u8, 2, 3];
                if table[core::hint::black_box(n as usize)] == 0 {
                    return false;
                }
            }
            for _ in 0..n.min(total) {
                if task.poll(&mut source, |_| ()) != Ok(true) {
                    return false;
                }
            }
            true
        }
        Mode::Ticks => {
            systick_start();
            let mut frame = 0u32;
            loop {
                let t0 = systick_now();
                let r = task.poll(&mut source, |_| ());
                let t1 = systick_now();
                match r {
                    // SysTick counts down, modulo 2^24.
                    Ok(true) => con.parts(
                        &[
                            (b"ticks ", frame),
                            (b" ", t0.wrapping_sub(t1) & 0x00FF_FFFF),
                        ],
                        b"",
                    ),
                    Ok(false) => break,
                    Err(_) => return false,
                }
                frame += 1;
            }
            con.write(b"done\n");
            true
        }
        Mode::Run => {
            let mut index = 0u32;
            while let Some(mut source) = routes.next_route() {
                if task.reset::<Infallible>().is_err() {
                    return false;
                }
                con.parts(&[(b"route ", index)], b"");
                index += 1;
                if !replay(con, &mut task, &mut source) {
                    return false;
                }
            }
            let (used, size) = stack_used();
            con.parts(&[(b"stack {\"used\":", used), (b",\"size\":", size)], b"}");
            con.parts(&[(b"monitor_size ", MONITOR_SIZE as u32)], b"");
            con.parts(&[(b"routes ", index), (b" frames ", routes_frames)], b"");
            con.write(b"done\n");
            !con.failed
        }
    }
}

/// One route through the task: event lines as they come, then the route's end.
fn replay(
    con: &mut Console,
    task: &mut MonitorTask<RamPin, RamPin>,
    source: &mut FlashFrames,
) -> bool {
    loop {
        #[cfg(feature = "json-report")]
        let polled = task.poll(source, |e| con.json(b"event ", e));
        #[cfg(not(feature = "json-report"))]
        let polled = task.poll(source, |_| ());
        match polled {
            Ok(true) => {}
            Ok(false) => break,
            Err(_) => {
                con.write(b"error: the monitor rejected a frame\n");
                return false;
            }
        }
    }
    let Ok(_done) = task.finish::<Infallible>() else {
        return false;
    };
    #[cfg(feature = "json-report")]
    {
        for e in &_done.events {
            con.json::<Event>(b"event ", e);
        }
        con.json(b"summary ", &_done.summary);
    }
    let mut line = [0u8; 128];
    match pins_line(&task.pins(), &mut line) {
        Some(n) => {
            con.write(line.get(..n).unwrap_or(&[]));
            con.write(b"\n");
            true
        }
        None => false,
    }
}

#[entry]
fn main() -> ! {
    let mut con = Console::open();
    let ok = run(&mut con) && !con.failed;
    debug::exit(if ok {
        debug::EXIT_SUCCESS
    } else {
        debug::EXIT_FAILURE
    });
    loop {
        core::hint::spin_loop();
    }
}

/// Release builds without `json-report` (the monitor path alone): no panic may survive optimisation. This handler refers to a symbol that
/// exists nowhere, so the release build only links if the compiler removed every call to it,
/// i.e. proved every panicking branch (index, overflow, unwrap...) unreachable.
#[cfg(not(any(debug_assertions, feature = "json-report", feature = "find-panics")))]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    extern "Rust" {
        #[link_name = "\n\nERROR: a panicking branch survived optimisation in the release build (see firmware-example/README.md, proof 2)\n"]
        fn panic_survived_optimisation() -> !;
    }
    // SAFETY: never called in a build that links.
    unsafe { panic_survived_optimisation() }
}

/// Debug builds, and builds with the JSON report (serde-json-core's serializer indexes its
/// buffer with checks the optimiser keeps): a panic is reported and fails the run.
#[cfg(any(debug_assertions, feature = "json-report", feature = "find-panics"))]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    if let Ok(mut out) = hio::hstdout() {
        let _ = out.write_all(b"error: panic\n");
    }
    debug::exit(debug::EXIT_FAILURE);
    loop {
        core::hint::spin_loop();
    }
}
