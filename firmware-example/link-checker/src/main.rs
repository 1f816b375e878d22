//! The QEMU board support of the SDS link checker (MPS2-AN386, Cortex-M4F): [`LinkTask`] on
//! the CMSDK UART0, the `link_fault` pin on user LED 0 of the FPGA's I/O block, SysTick as the
//! clock.
//!
//! Modes, from the semihosting command line (`-semihosting-config ...,arg=checker,arg=MODE`):
//! * `serve` (default): serves the link on UART0 until QEMU is stopped; after each route's
//!   summary it prints `route {...}` over semihosting (the route's counts, the pin, the stack
//!   high-water mark so far). Between bytes the core sleeps in WFI, woken by the UART's receive
//!   interrupt or a 1 ms tick of TIMER0 (for the timeout); the clock is SysTick, which under
//!   `-icount` runs with the instructions executed and, while the core sleeps, with real time:
//!   a doer that stops sending gives `NONEWDATA`, and the pin after the window;
//! * `serve slots`: the same, on a clock that counts received messages, one frame period each
//!   (`NONEWDATA` after `link.timeout` messages in a row that are not frames): what the link
//!   shows then depends on the bytes alone, never on how fast the host ran the doer;
//! * `bench N`: feeds the first N messages of the wire capture in flash (`SDS_LINK_WIRE`) to the
//!   checker, answering on UART0, and exits: the instruction-count plugin's total for `bench N`
//!   minus `bench 0` is the checker's share;
//! * `ticks`: feeds the capture one message at a time and prints `ticks MESSAGE T` for each,
//!   T the SysTick count of the message; under `-icount shift=0` it advances with the
//!   instructions executed (40 a tick).
#![no_std]
#![no_main]

use core::convert::Infallible;

use cortex_m_rt::entry;
use cortex_m_semihosting::{debug, hio, nr};
use embedded_hal::digital::{ErrorType, OutputPin};
use embedded_hal_nb::{nb, serial};
use link_checker::{decimal, LinkTask, Ticks};
use monitor_core::link::{LinkConfig, RouteState};

include!(concat!(env!("OUT_DIR"), "/wire.rs"));

/// SysTick ticks per microsecond: the MPS2's 25 MHz system clock.
const TICKS_PER_US: u32 = 25;

// --- CMSDK APB UART (ARM DDI0479C §4.3): data, state, control, ..., baud divider ---------------
const UART0: usize = 0x4000_4000;
const DATA: usize = 0x00;
const STATE: usize = 0x04;
const CTRL: usize = 0x08;
const BAUDDIV: usize = 0x10;
const STATE_TX_FULL: u32 = 1 << 0;
const STATE_RX_FULL: u32 = 1 << 1;
const STATE_RX_OVERRUN: u32 = 1 << 3;
const INTCLEAR: usize = 0x0C;
const CTRL_TX_EN: u32 = 1 << 0;
const CTRL_RX_EN: u32 = 1 << 1;
const CTRL_RX_INT_EN: u32 = 1 << 3;
const INT_RX: u32 = 1 << 1;
/// NVIC numbers of the MPS2-AN385/AN386 (QEMU's mps2.c): UART0 receive, TIMER0.
const IRQ_UART0_RX: u32 = 0;
const IRQ_TIMER0: u32 = 8;

fn reg_read(addr: usize) -> u32 {
    // SAFETY: a device register of the board's memory map, word aligned.
    unsafe { core::ptr::read_volatile(addr as *const u32) }
}

fn reg_write(addr: usize, v: u32) {
    // SAFETY: a device register of the board's memory map, word aligned.
    unsafe { core::ptr::write_volatile(addr as *mut u32, v) }
}

/// The CMSDK APB UART, polled: a one-byte receive and a one-byte transmit register.
struct CmsdkUart {
    base: usize,
}

impl CmsdkUart {
    /// Enables receive and transmit. The divider is the smallest the UART takes (16); QEMU does
    /// not pace the line by it, a board would set its baud rate here.
    fn new(base: usize) -> Self {
        reg_write(base + BAUDDIV, 16);
        reg_write(base + CTRL, CTRL_TX_EN | CTRL_RX_EN);
        CmsdkUart { base }
    }
}

impl CmsdkUart {
    /// A byte in the receive register.
    fn rx_ready(&self) -> bool {
        reg_read(self.base + STATE) & STATE_RX_FULL != 0
    }
}

// --- idling: WFI with interrupts masked (PRIMASK), woken by a pending interrupt -----------------
const TIMER0: usize = 0x4000_0000;
const TIMER_CTRL: usize = 0x00;
const TIMER_RELOAD: usize = 0x08;
const TIMER_INTCLEAR: usize = 0x0C;
const NVIC_ISER0: usize = 0xE000_E100;
const NVIC_ICPR0: usize = 0xE000_E280;

/// Arms the wake-ups of [`idle`]: UART0's receive interrupt and a 1 ms TIMER0 tick, enabled in
/// the NVIC but masked by PRIMASK, so no handler runs: a pending interrupt only ends a WFI.
fn idle_setup() {
    // SAFETY: masks interrupts (PRIMASK); nothing here relies on a handler running.
    unsafe { core::arch::asm!("cpsid i", options(nomem, nostack, preserves_flags)) };
    reg_write(UART0 + CTRL, CTRL_TX_EN | CTRL_RX_EN | CTRL_RX_INT_EN);
    reg_write(TIMER0 + TIMER_RELOAD, TICKS_PER_US * 1000);
    // Enable, interrupt enable.
    reg_write(TIMER0 + TIMER_CTRL, 1 | (1 << 3));
    reg_write(NVIC_ISER0, (1 << IRQ_UART0_RX) | (1 << IRQ_TIMER0));
}

/// Sleeps until a byte arrives or the next 1 ms tick, unless a byte is already waiting.
fn idle(uart: &CmsdkUart) {
    // Clear the sources, then their pending bits: a byte arriving after this sets them again
    // and ends the WFI at once; one that arrived before is seen by `rx_ready`.
    reg_write(UART0 + INTCLEAR, INT_RX);
    reg_write(TIMER0 + TIMER_INTCLEAR, 1);
    reg_write(NVIC_ICPR0, (1 << IRQ_UART0_RX) | (1 << IRQ_TIMER0));
    if uart.rx_ready() {
        return;
    }
    // SAFETY: waits for an interrupt; touches no memory.
    unsafe { core::arch::asm!("wfi", options(nomem, nostack, preserves_flags)) };
}

/// A byte arrived while the last one was still unread: one byte is lost.
#[derive(Debug)]
struct Overrun;

impl serial::Error for Overrun {
    fn kind(&self) -> serial::ErrorKind {
        serial::ErrorKind::Overrun
    }
}

impl serial::ErrorType for CmsdkUart {
    type Error = Overrun;
}

impl serial::Read<u8> for CmsdkUart {
    fn read(&mut self) -> nb::Result<u8, Overrun> {
        let state = reg_read(self.base + STATE);
        if state & STATE_RX_OVERRUN != 0 {
            // Write one to clear.
            reg_write(self.base + STATE, STATE_RX_OVERRUN);
            return Err(nb::Error::Other(Overrun));
        }
        if state & STATE_RX_FULL == 0 {
            return Err(nb::Error::WouldBlock);
        }
        Ok(reg_read(self.base + DATA) as u8)
    }
}

impl serial::Write<u8> for CmsdkUart {
    fn write(&mut self, byte: u8) -> nb::Result<(), Overrun> {
        if reg_read(self.base + STATE) & STATE_TX_FULL != 0 {
            return Err(nb::Error::WouldBlock);
        }
        reg_write(self.base + DATA, u32::from(byte));
        Ok(())
    }
    fn flush(&mut self) -> nb::Result<(), Overrun> {
        if reg_read(self.base + STATE) & STATE_TX_FULL != 0 {
            return Err(nb::Error::WouldBlock);
        }
        Ok(())
    }
}

/// For `bench` and `ticks`: bytes from the wire capture in flash instead of the receive
/// register, `budget` messages at a time; answers to the real UART.
struct FlashWire {
    bytes: &'static [u8],
    pos: usize,
    budget: u32,
    tx: CmsdkUart,
}

impl serial::ErrorType for FlashWire {
    type Error = Overrun;
}

impl serial::Read<u8> for FlashWire {
    fn read(&mut self) -> nb::Result<u8, Overrun> {
        if self.budget == 0 {
            return Err(nb::Error::WouldBlock);
        }
        let &b = self.bytes.get(self.pos).ok_or(nb::Error::WouldBlock)?;
        self.pos += 1;
        if b == 0 {
            self.budget -= 1;
        }
        Ok(b)
    }
}

impl serial::Write<u8> for FlashWire {
    fn write(&mut self, byte: u8) -> nb::Result<(), Overrun> {
        self.tx.write(byte)
    }
    fn flush(&mut self) -> nb::Result<(), Overrun> {
        self.tx.flush()
    }
}

// --- the link_fault pin: user LED 0 (bit 0 of the FPGA I/O block's LED register) ---------------
const FPGAIO_LED: usize = 0x4002_8000;

/// `link_fault` on LED 0. On a real board, pass the HAL's GPIO pin instead.
struct LedPin;

impl LedPin {
    fn set(&mut self, on: bool) {
        let v = reg_read(FPGAIO_LED);
        reg_write(FPGAIO_LED, if on { v | 1 } else { v & !1 });
    }
}

impl ErrorType for LedPin {
    type Error = Infallible;
}

impl OutputPin for LedPin {
    fn set_low(&mut self) -> Result<(), Infallible> {
        self.set(false);
        Ok(())
    }
    fn set_high(&mut self) -> Result<(), Infallible> {
        self.set(true);
        Ok(())
    }
}

// --- SysTick, free-running (ARMv7-M architecture registers) --------------------------------------
const SYST_CSR: usize = 0xE000_E010;
const SYST_RVR: usize = 0xE000_E014;
const SYST_CVR: usize = 0xE000_E018;

fn systick_start() {
    reg_write(SYST_RVR, 0x00FF_FFFF);
    reg_write(SYST_CVR, 0);
    // Enable, processor clock, no interrupt.
    reg_write(SYST_CSR, 0b101);
}

fn systick_now() -> u32 {
    reg_read(SYST_CVR)
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
    /// Text and numbers, in turn, then `tail` and a newline.
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
    /// `slots`: the clock counts received messages.
    Serve {
        slots: bool,
    },
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
        return Some(Mode::Serve { slots: false }); // no command line: the default mode
    }
    let line = buf.get(..block[1].min(buf.len())).unwrap_or(&[]);
    let mut words = line
        .split(|&b| b == b' ' || b == 0)
        .filter(|w| !w.is_empty());
    let _program = words.next();
    match words.next() {
        None => Some(Mode::Serve { slots: false }),
        Some(b"serve") => match words.next() {
            None => Some(Mode::Serve { slots: false }),
            Some(b"slots") => Some(Mode::Serve { slots: true }),
            Some(_) => None,
        },
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

/// Bytes of the stack used so far: cortex-m-rt painted `_stack_end.._stack_start` with
/// 0xCCCC_CCCC before `main`; the lowest word that lost its paint is the high-water mark.
fn stack_used() -> u32 {
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
    (start - p) as u32
}

/// Serves the link until QEMU is stopped; `false` on a fault the board cannot go on from.
/// `slots`: the clock counts received messages, one frame period each.
fn serve(con: &mut Console, slots: bool) -> bool {
    let Ok(mut task) = LinkTask::<_, _>::new(LinkConfig::DEFAULT, CmsdkUart::new(UART0), LedPin)
    else {
        con.write(b"error: the checker could not start\n");
        return false;
    };
    systick_start();
    idle_setup();
    let mut clock = Ticks::new(systick_now(), TICKS_PER_US);
    con.parts(&[(b"serving ", u32::from(slots))], b"");
    let mut seen = 0;
    let mut route = RouteState::Idle;
    let mut routes = 0;
    let mut slot_clock: u64 = 0;
    loop {
        // The clock's reading is taken on every turn (at least every 1 ms tick), so SysTick's
        // 0.67 s wrap is never missed.
        let ticks = clock.now_us(systick_now());
        let now = if slots { slot_clock } else { ticks };
        let taken = match task.poll(now) {
            Ok(n) => n,
            Err(_) => {
                con.write(b"error: the link_fault pin cannot be driven\n");
                return false;
            }
        };
        if taken == 0 {
            idle(task.uart_mut());
        }
        if task.messages() == seen {
            continue;
        }
        if slots {
            // One frame period per message received (the route's, from its start).
            let period = task.checker().timeout_us() / u64::from(LinkConfig::DEFAULT.timeout);
            let new = u64::from(task.messages().wrapping_sub(seen));
            slot_clock = slot_clock.saturating_add(period.saturating_mul(new));
        }
        seen = task.messages();
        let s = task.checker().status();
        if s.route == RouteState::Finished && route != RouteState::Finished {
            let pin = task.pin();
            con.parts(
                &[
                    (b"route {\"index\":", routes),
                    (b",\"messages\":", seen),
                    (b",\"accepted\":", s.accepted),
                    (b",\"segments\":", s.segments),
                    (b",\"pin_rises\":", pin.rises),
                    (b",\"pin_high\":", pin.high as u32),
                    (b",\"rx_errors\":", task.rx_errors()),
                    (b",\"tx_dropped\":", task.tx_dropped()),
                    (b",\"stack\":", stack_used()),
                ],
                b"}",
            );
            routes += 1;
        }
        route = s.route;
    }
}

/// `bench N` / `ticks` over the capture in flash.
fn measure(con: &mut Console, bench: Option<u32>) -> bool {
    let wire = FlashWire {
        bytes: &WIRE,
        pos: 0,
        budget: 0,
        tx: CmsdkUart::new(UART0),
    };
    let Ok(mut task) = LinkTask::<_, _>::new(LinkConfig::DEFAULT, wire, LedPin) else {
        return false;
    };
    // The clock stands still: no timeout in a measurement.
    match bench {
        Some(n) => {
            task.uart_mut().budget = n;
            loop {
                match task.poll(0) {
                    Ok(0) => return true,
                    Ok(_) => {}
                    Err(_) => return false,
                }
            }
        }
        None => {
            systick_start();
            let messages = WIRE.iter().filter(|&&b| b == 0).count() as u32;
            for m in 0..messages {
                task.uart_mut().budget = 1;
                let t0 = systick_now();
                loop {
                    match task.poll(0) {
                        Ok(0) => break,
                        Ok(_) => {}
                        Err(_) => return false,
                    }
                }
                let t1 = systick_now();
                // SysTick counts down, modulo 2^24.
                con.parts(
                    &[(b"ticks ", m), (b" ", t0.wrapping_sub(t1) & 0x00FF_FFFF)],
                    b"",
                );
            }
            con.parts(&[(b"stack ", stack_used())], b"");
            con.write(b"done\n");
            !con.failed
        }
    }
}

#[entry]
fn main() -> ! {
    let mut con = Console::open();
    let ok = match mode() {
        Some(Mode::Serve { slots }) => serve(&mut con, slots),
        Some(Mode::Bench(n)) => measure(&mut con, Some(n)),
        Some(Mode::Ticks) => measure(&mut con, None),
        None => {
            con.write(b"error: unknown mode (use serve, serve slots, bench N or ticks)\n");
            false
        }
    };
    debug::exit(if ok && !con.failed {
        debug::EXIT_SUCCESS
    } else {
        debug::EXIT_FAILURE
    });
    loop {
        core::hint::spin_loop();
    }
}

/// Release builds: no panic may survive optimisation. This handler refers to a symbol that
/// exists nowhere, so the release build only links if the compiler removed every call to it,
/// i.e. proved every panicking branch (index, overflow, unwrap...) of the checker unreachable.
#[cfg(not(any(debug_assertions, feature = "find-panics")))]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    extern "Rust" {
        #[link_name = "\n\nERROR: a panicking branch survived optimisation in the link checker's release build (see firmware-example/README.md)\n"]
        fn panic_survived_optimisation() -> !;
    }
    // SAFETY: never called in a build that links.
    unsafe { panic_survived_optimisation() }
}

/// Debug builds and `find-panics`: the pin goes high (the checker can no longer vouch for the
/// link: the safe side), the panic is reported and the run fails.
#[cfg(any(debug_assertions, feature = "find-panics"))]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    LedPin.set(true);
    if let Ok(mut out) = hio::hstdout() {
        let _ = out.write_all(b"error: panic\n");
    }
    debug::exit(debug::EXIT_FAILURE);
    loop {
        core::hint::spin_loop();
    }
}
