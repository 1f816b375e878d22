//! `sds_link_*`: the monitor on a live link (docs/SCORE.md, "Live link"; docs/C-API.md, "The
//! live link"). The checker's side (`sds_link_checker_*`: bytes in, answers out through the
//! caller's write function) in memory the caller owns, as `sds_monitor`; and the doer's side
//! for C (`sds_link_encode_*` writes a start, a frame or an end as it goes on the wire,
//! `sds_link_decode` reads one of the checker's answers).

use core::ffi::c_void;
use core::mem::{align_of, size_of};

use monitor_core::link::{
    self, CheckStatus, Checker, Deframer, LinkConfig, LinkConfigError, LinkEvent, LinkState,
    Message, RouteState, StatusCounts,
};
use monitor_core::Frame;

use crate::config::sds_config;
use crate::event::sds_event;
use crate::frame::sds_frame;
use crate::result::{code, sds_result};
use crate::summary::sds_summary;
use crate::{guard, usable};

/// Marks an initialised checker, so that a zeroed or never-initialised buffer is refused.
const MAGIC: u32 = 0x5344_534C; // "SDSL"

/// Bytes of the longest message on the wire (COBS-encoded, with its 0x00 delimiter): an output
/// buffer of this size holds any `sds_link_encode_*` result.
pub const SDS_LINK_MAX_ENCODED: usize = 118;
const _: () = assert!(SDS_LINK_MAX_ENCODED == link::MAX_ENCODED);

/// Check statuses, in the order of `sds_link_status.counts` (Profile 4's names).
pub const SDS_LINK_STATUSES: usize = 6;

/// The link settings (`link.*`): Profile 4's counter tolerance and timeout, and the
/// VALID/INVALID window. Start from `sds_link_config_default()`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[allow(non_camel_case_types)]
pub struct sds_link_config {
    /// Largest counter step still accepted (3): steps 2 ..= this are `OKSOMELOST`.
    pub max_delta: u16,
    /// Frame periods without a frame before `NONEWDATA` (3).
    pub timeout: u16,
    /// Statuses the link state is judged over (20; 1 ..= 32).
    pub window: u8,
    /// Bad statuses in the window still `VALID` (2; below `window`).
    pub max_errors: u8,
}

impl From<sds_link_config> for LinkConfig {
    fn from(c: sds_link_config) -> Self {
        LinkConfig {
            max_delta: c.max_delta,
            timeout: c.timeout,
            window: c.window,
            max_errors: c.max_errors,
        }
    }
}

impl From<LinkConfigError> for sds_result {
    fn from(e: LinkConfigError) -> Self {
        match e {
            LinkConfigError::MaxDelta => sds_result::LinkConfigMaxDelta,
            LinkConfigError::Timeout => sds_result::LinkConfigTimeout,
            LinkConfigError::Window => sds_result::LinkConfigWindow,
            LinkConfigError::MaxErrors => sds_result::LinkConfigMaxErrors,
            // SDS_CAPACITY is the core's default, checked when the library is built.
            LinkConfigError::Capacity => sds_result::ConfigCapacity,
        }
    }
}

/// The default link settings: `max_delta` 3, `timeout` 3, `window` 20, `max_errors` 2.
///
/// ```c
/// sds_link_config lc = sds_link_config_default();
/// lc.timeout = 5;   /* five frame periods before NONEWDATA */
/// ```
#[no_mangle]
pub extern "C" fn sds_link_config_default() -> sds_link_config {
    let d = LinkConfig::DEFAULT;
    sds_link_config {
        max_delta: d.max_delta,
        timeout: d.timeout,
        window: d.window,
        max_errors: d.max_errors,
    }
}

/// The link state and counts of the current route (what a status message carries).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[allow(non_camel_case_types)]
pub struct sds_link_status {
    /// The link is `VALID` (the `link_fault` pin is the inverse).
    pub valid: bool,
    /// `SDS_LINK_ROUTE_IDLE`, `_RUNNING`, `_FINISHED` or `_REFUSED`.
    pub route: u32,
    /// Counter of the last frame message that passed its check (0 before any).
    pub last_counter: u16,
    /// Frame messages per check status: `counts[SDS_LINK_STATUS_OK]` ... (route so far).
    pub counts: [u32; SDS_LINK_STATUSES],
    /// Frames given to the monitor in the route.
    pub accepted: u32,
    /// Segments started in the route.
    pub segments: u32,
}

/// Index of `OK` in `counts`: counter +1.
pub const SDS_LINK_STATUS_OK: usize = 0;
/// Index of `OKSOMELOST`: counter +2 ..= `max_delta` (accepted; the frames between lost).
pub const SDS_LINK_STATUS_OKSOMELOST: usize = 1;
/// Index of `WRONGSEQUENCE`: a larger jump (dropped; the next accepted frame starts a segment).
pub const SDS_LINK_STATUS_WRONGSEQUENCE: usize = 2;
/// Index of `REPEATED`: the same counter (dropped).
pub const SDS_LINK_STATUS_REPEATED: usize = 3;
/// Index of `ERROR`: length, data id, CRC, COBS or layout wrong (dropped).
pub const SDS_LINK_STATUS_ERROR: usize = 4;
/// Index of `NONEWDATA`: no frame for `timeout` frame periods.
pub const SDS_LINK_STATUS_NONEWDATA: usize = 5;
const _: () = assert!(CheckStatus::ALL.len() == SDS_LINK_STATUSES);

/// No route started: frames are checked, not monitored.
pub const SDS_LINK_ROUTE_IDLE: u32 = 0;
/// A route is running.
pub const SDS_LINK_ROUTE_RUNNING: u32 = 1;
/// The route ended; its summary was sent.
pub const SDS_LINK_ROUTE_FINISHED: u32 = 2;
/// The last start's configuration was refused.
pub const SDS_LINK_ROUTE_REFUSED: u32 = 3;

fn counts(c: &StatusCounts) -> [u32; SDS_LINK_STATUSES] {
    CheckStatus::ALL.map(|s| c.get(s))
}

impl From<&link::Status> for sds_link_status {
    fn from(s: &link::Status) -> Self {
        sds_link_status {
            valid: s.link == LinkState::Valid,
            route: match s.route {
                RouteState::Idle => SDS_LINK_ROUTE_IDLE,
                RouteState::Running => SDS_LINK_ROUTE_RUNNING,
                RouteState::Finished => SDS_LINK_ROUTE_FINISHED,
                RouteState::Refused => SDS_LINK_ROUTE_REFUSED,
            },
            last_counter: s.last_counter,
            counts: counts(&s.counts),
            accepted: s.accepted,
            segments: s.segments,
        }
    }
}

/// The checker of one link (opaque). It lives in a buffer the caller owns: at least
/// `sds_link_checker_size()` bytes aligned to `sds_link_checker_align()`, for example an
/// `sds_link_checker_storage`. Nothing is allocated and nothing needs freeing.
#[allow(non_camel_case_types)]
pub struct sds_link_checker {
    magic: u32,
    checker: Checker,
}

/// 64-bit words of `sds_link_checker_storage`.
pub const SDS_LINK_CHECKER_STORAGE_WORDS: usize = 128;

/// Memory for one checker with the right size and alignment for every target:
/// `sds_link_checker_storage mem; sds_link_checker *k = (sds_link_checker *)&mem;`.
#[repr(C)]
#[allow(non_camel_case_types)]
pub struct sds_link_checker_storage {
    /// Opaque.
    pub _words: [u64; SDS_LINK_CHECKER_STORAGE_WORDS],
}

// A bigger checker is a compile error here: raise SDS_LINK_CHECKER_STORAGE_WORDS (an ABI change).
const _: () = assert!(size_of::<sds_link_checker>() <= size_of::<sds_link_checker_storage>());
const _: () = assert!(align_of::<sds_link_checker>() <= align_of::<sds_link_checker_storage>());

/// Bytes a checker needs (at most `sizeof(sds_link_checker_storage)`).
///
/// ```c
/// assert(sds_link_checker_size() <= sizeof(sds_link_checker_storage));
/// ```
#[no_mangle]
pub extern "C" fn sds_link_checker_size() -> usize {
    size_of::<sds_link_checker>()
}

/// Alignment a checker's buffer needs, in bytes.
///
/// ```c
/// assert(sds_link_checker_align() <= _Alignof(sds_link_checker_storage));   /* C11 */
/// ```
#[no_mangle]
pub extern "C" fn sds_link_checker_align() -> usize {
    align_of::<sds_link_checker>()
}

/// Where the checker's answers go: called with `ctx` and one whole encoded message (its 0x00
/// delimiter included) each time the checker answers; write the bytes to the link (a UART, a
/// socket). The bytes are valid during the call only.
#[allow(non_camel_case_types)]
pub type sds_link_write =
    Option<unsafe extern "C" fn(ctx: *mut c_void, bytes: *const u8, len: usize)>;

/// The initialised checker behind `k`, to change it.
///
/// # Safety
/// `k` is NULL or points to at least `sds_link_checker_size()` readable bytes that nothing
/// else accesses during the call (other memory is refused by its magic number).
unsafe fn state_mut<'a>(k: *mut sds_link_checker) -> Result<&'a mut Checker, sds_result> {
    if k.is_null() {
        return Err(sds_result::NullPointer);
    }
    if !k.is_aligned() {
        return Err(sds_result::BufferMisaligned);
    }
    // SAFETY: non-NULL, aligned and readable (the caller's promise); any bits are a valid u32.
    let magic = unsafe { core::ptr::addr_of!((*k).magic).read() };
    if magic != MAGIC {
        return Err(sds_result::NotInitialized);
    }
    // SAFETY: the magic says sds_link_checker_init wrote a valid checker here; the caller
    // promises exclusive access for the duration of the call.
    Ok(unsafe { &mut (*k).checker })
}

/// Initialises a checker with no route yet in the caller's buffer `checker` of `len` bytes,
/// with the link settings `config`. On failure the buffer is left untouched. Re-initialising
/// is a checker reset (the doer's counters are judged afresh).
///
/// Errors: `SDS_RESULT_NULL_POINTER`, `SDS_RESULT_BUFFER_TOO_SMALL`,
/// `SDS_RESULT_BUFFER_MISALIGNED`, `SDS_RESULT_MISALIGNED_POINTER` (`config`),
/// `SDS_RESULT_LINK_CONFIG_*`.
///
/// ```c
/// static sds_link_checker_storage mem;
/// sds_link_checker *k = (sds_link_checker *)&mem;
/// sds_link_config lc = sds_link_config_default();
/// sds_result r = sds_link_checker_init(k, sizeof mem, &lc);   /* SDS_RESULT_OK */
/// ```
///
/// # Safety
/// `checker` is NULL or writable for `len` bytes, and not used by anyone else during the call;
/// `config` is NULL or points to a readable `sds_link_config`.
#[no_mangle]
pub unsafe extern "C" fn sds_link_checker_init(
    checker: *mut sds_link_checker,
    len: usize,
    config: *const sds_link_config,
) -> sds_result {
    guard(|| {
        if checker.is_null() {
            return sds_result::NullPointer;
        }
        if let Err(e) = usable(config) {
            return e;
        }
        if len < size_of::<sds_link_checker>() {
            return sds_result::BufferTooSmall;
        }
        if !checker.is_aligned() {
            return sds_result::BufferMisaligned;
        }
        // SAFETY: usable; the caller promises a readable sds_link_config (plain integers).
        let config = LinkConfig::from(unsafe { config.read() });
        let c = match Checker::new(config) {
            Ok(c) => c,
            Err(e) => return e.into(),
        };
        // SAFETY: non-NULL, aligned, writable for len >= size_of::<sds_link_checker>() bytes;
        // the old contents (plain data) are overwritten, not read.
        unsafe {
            checker.write(sds_link_checker {
                magic: MAGIC,
                checker: c,
            })
        };
        sds_result::Ok
    })
}

/// Calls the C write function for each answer.
fn writer(
    write: unsafe extern "C" fn(*mut c_void, *const u8, usize),
    ctx: *mut c_void,
) -> impl FnMut(&[u8]) {
    move |bytes: &[u8]| {
        // SAFETY: the caller of sds_link_receive/poll promised a callable `write` that takes
        // `ctx`; the bytes are valid for the call.
        unsafe { write(ctx, bytes.as_ptr(), bytes.len()) }
    }
}

/// Gives the checker the bytes `bytes[0 .. len]` received at time `now_us` (microseconds,
/// monotonic, the caller's clock). Each answer (events, status, summary) goes to `write(ctx,
/// ...)` before the call returns. Any bytes are fine: noise, cut or corrupted messages get the
/// check status `ERROR` and are dropped.
///
/// Errors: `SDS_RESULT_NULL_POINTER` (`checker`, `write`, or `bytes` with `len > 0`),
/// `SDS_RESULT_BUFFER_MISALIGNED`, `SDS_RESULT_NOT_INITIALIZED`.
///
/// ```c
/// static void to_uart(void *ctx, const uint8_t *bytes, size_t len) { uart_write(ctx, bytes, len); }
/// sds_link_receive(k, rx, n, now_us(), to_uart, uart);
/// ```
///
/// # Safety
/// `checker` is NULL or an initialised checker nobody else uses during the call; `bytes` is
/// readable for `len` bytes (or NULL with `len` 0); `write` may be called with `ctx`.
#[no_mangle]
pub unsafe extern "C" fn sds_link_receive(
    checker: *mut sds_link_checker,
    bytes: *const u8,
    len: usize,
    now_us: u64,
    write: sds_link_write,
    ctx: *mut c_void,
) -> sds_result {
    guard(|| {
        code((|| {
            let write = write.ok_or(sds_result::NullPointer)?;
            if bytes.is_null() && len > 0 {
                return Err(sds_result::NullPointer);
            }
            // SAFETY: the caller's promise on `checker`.
            let k = unsafe { state_mut(checker) }?;
            let input = if len == 0 {
                &[][..]
            } else {
                // SAFETY: non-NULL and readable for len bytes (the caller's promise).
                unsafe { core::slice::from_raw_parts(bytes, len) }
            };
            k.receive(input, now_us, &mut writer(write, ctx));
            Ok(())
        })())
    })
}

/// Checks the timeout at time `now_us`: with a route running and no frame for `timeout` frame
/// periods, the check status is `NONEWDATA` and a status message goes to `write`. Call it from
/// a timer set to `sds_link_checker_deadline` (or often).
///
/// ```c
/// sds_link_poll(k, now_us(), to_uart, uart);
/// ```
///
/// # Safety
/// As `sds_link_receive`.
#[no_mangle]
pub unsafe extern "C" fn sds_link_poll(
    checker: *mut sds_link_checker,
    now_us: u64,
    write: sds_link_write,
    ctx: *mut c_void,
) -> sds_result {
    guard(|| {
        code((|| {
            let write = write.ok_or(sds_result::NullPointer)?;
            // SAFETY: the caller's promise on `checker`.
            let k = unsafe { state_mut(checker) }?;
            k.poll(now_us, &mut writer(write, ctx));
            Ok(())
        })())
    })
}

/// The time by which `sds_link_poll` must run for `NONEWDATA` to be on time into `*deadline_us`;
/// `SDS_RESULT_UNDEFINED` (and `*deadline_us` unchanged) while no timeout runs (no route).
///
/// ```c
/// uint64_t t;
/// if (sds_link_checker_deadline(k, &t) == SDS_RESULT_OK) timer_set(t);
/// ```
///
/// # Safety
/// `checker` is NULL or an initialised checker nobody else uses during the call;
/// `deadline_us` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn sds_link_checker_deadline(
    checker: *mut sds_link_checker,
    deadline_us: *mut u64,
) -> sds_result {
    guard(|| {
        code((|| {
            usable(deadline_us)?;
            // SAFETY: the caller's promise on `checker`.
            let k = unsafe { state_mut(checker) }?;
            let t = k.deadline().ok_or(sds_result::Undefined)?;
            // SAFETY: usable; the caller promises a writable u64.
            unsafe { deadline_us.write(t) };
            Ok(())
        })())
    })
}

/// The link state and the route's counts so far into `*status` (what the checker's next status
/// message says; `status->valid` false means: drive the `link_fault` output).
///
/// ```c
/// sds_link_status s;
/// sds_link_checker_status(k, &s);
/// gpio_write(LINK_FAULT_PIN, !s.valid);
/// ```
///
/// # Safety
/// `checker` is NULL or an initialised checker nobody else uses during the call; `status` is
/// NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn sds_link_checker_status(
    checker: *mut sds_link_checker,
    status: *mut sds_link_status,
) -> sds_result {
    guard(|| {
        code((|| {
            usable(status)?;
            // SAFETY: the caller's promise on `checker`.
            let k = unsafe { state_mut(checker) }?;
            // SAFETY: usable; the caller promises a writable sds_link_status.
            unsafe { status.write((&k.status()).into()) };
            Ok(())
        })())
    })
}

/// Writes `message` (counter `counter`) into `out[0 .. cap]` as it goes on the wire.
///
/// # Safety
/// `out` is writable for `cap` bytes and `written` writable (both checked non-NULL here).
unsafe fn encode(
    message: &Message,
    counter: u16,
    out: *mut u8,
    cap: usize,
    written: *mut usize,
) -> Result<(), sds_result> {
    usable(written)?;
    if out.is_null() {
        return Err(sds_result::NullPointer);
    }
    let mut buf = [0u8; link::MAX_ENCODED];
    let n = link::encode(message, counter, &mut buf);
    if n > cap {
        return Err(sds_result::OutputTooSmall);
    }
    // SAFETY: out is writable for cap >= n bytes (the caller's promise), and does not overlap
    // the local buffer.
    unsafe {
        core::ptr::copy_nonoverlapping(buf.as_ptr(), out, n);
        written.write(n);
    }
    Ok(())
}

/// The doer's side: writes a start message (the route's monitor configuration `config`, with
/// E2E counter `counter`) into `out[0 .. cap]`, COBS-encoded and delimited; `*written` gets its
/// length (at most `SDS_LINK_MAX_ENCODED`). Send it until a status message answers it.
///
/// Errors: `SDS_RESULT_NULL_POINTER`, `SDS_RESULT_MISALIGNED_POINTER`,
/// `SDS_RESULT_OUTPUT_TOO_SMALL`, `SDS_RESULT_CONFIG_*` (the checker would refuse it).
///
/// ```c
/// uint8_t wire[SDS_LINK_MAX_ENCODED];
/// size_t n;
/// sds_config c = sds_config_default();
/// sds_link_encode_start(&c, 0, wire, sizeof wire, &n);
/// ```
///
/// # Safety
/// `config` is NULL or readable; `out` is NULL or writable for `cap` bytes; `written` is NULL
/// or writable.
#[no_mangle]
pub unsafe extern "C" fn sds_link_encode_start(
    config: *const sds_config,
    counter: u16,
    out: *mut u8,
    cap: usize,
    written: *mut usize,
) -> sds_result {
    guard(|| {
        code((|| {
            usable(config)?;
            // SAFETY: usable; the caller promises a readable sds_config.
            let c = unsafe { config.read() }.to_core()?;
            // SAFETY: forwarded from the caller.
            unsafe { encode(&Message::Start(c), counter, out, cap, written) }
        })())
    })
}

/// The doer's side: writes a frame message (E2E counter `counter`, +1 per frame) into
/// `out[0 .. cap]`; `*written` gets its length (47 bytes).
///
/// Errors: `SDS_RESULT_NULL_POINTER`, `SDS_RESULT_MISALIGNED_POINTER`,
/// `SDS_RESULT_OUTPUT_TOO_SMALL`, `SDS_RESULT_FRAME_*` (the checker would count it `ERROR`).
///
/// ```c
/// sds_frame f = {0};
/// f.speed = 8.0f;
/// sds_link_encode_frame(&f, counter++, wire, sizeof wire, &n);
/// ```
///
/// # Safety
/// As `sds_link_encode_start`, with `frame` for `config`.
#[no_mangle]
pub unsafe extern "C" fn sds_link_encode_frame(
    frame: *const sds_frame,
    counter: u16,
    out: *mut u8,
    cap: usize,
    written: *mut usize,
) -> sds_result {
    guard(|| {
        code((|| {
            usable(frame)?;
            // SAFETY: usable; the caller promises a readable sds_frame.
            let f = Frame::from(unsafe { &*frame });
            f.validate()?;
            // SAFETY: forwarded from the caller.
            unsafe { encode(&Message::Frame(f), counter, out, cap, written) }
        })())
    })
}

/// The doer's side: writes an end message (`frames`: frame messages sent for the route, E2E
/// counter `counter`) into `out[0 .. cap]`. Send it until the summary answers it.
///
/// ```c
/// sds_link_encode_end(frames_sent, 0, wire, sizeof wire, &n);
/// ```
///
/// # Safety
/// `out` is NULL or writable for `cap` bytes; `written` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn sds_link_encode_end(
    frames: u32,
    counter: u16,
    out: *mut u8,
    cap: usize,
    written: *mut usize,
) -> sds_result {
    // SAFETY: forwarded from the caller.
    guard(|| code(unsafe { encode(&Message::End { frames }, counter, out, cap, written) }))
}

/// Which member of an `sds_link_event` is set.
#[allow(non_camel_case_types)]
pub type sds_link_event_kind = u32;
/// One of the monitor's events: `monitor` is set.
pub const SDS_LINK_EVENT_MONITOR: sds_link_event_kind = 1;
/// The frame starts segment `value` (0-based): the monitor started afresh.
pub const SDS_LINK_EVENT_SEGMENT: sds_link_event_kind = 2;
/// The link became `INVALID` (`value`: bad statuses in the window).
pub const SDS_LINK_EVENT_LINK_FAULT: sds_link_event_kind = 3;
/// The link became `VALID` again (`value`: bad statuses in the window).
pub const SDS_LINK_EVENT_LINK_RESTORED: sds_link_event_kind = 4;

/// An event of the checker.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[allow(non_camel_case_types)]
pub struct sds_link_event {
    /// `SDS_LINK_EVENT_*`.
    pub kind: sds_link_event_kind,
    /// Counter of the frame message that raised it (for a segment's end events, its last
    /// accepted frame).
    pub frame_counter: u16,
    /// The segment's index, or the bad statuses of the window.
    pub value: u32,
    /// The monitor's event when `kind == SDS_LINK_EVENT_MONITOR` (else zero).
    pub monitor: sds_event,
}

/// What the checker's route summary says (the answer to an end).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[allow(non_camel_case_types)]
pub struct sds_link_summary {
    /// The monitor's counts, summed over the segments.
    pub route: sds_summary,
    /// Frames lost inside segments.
    pub gaps: u32,
    /// Segments.
    pub segments: u32,
    /// Frame messages per check status (`SDS_LINK_STATUS_*` indices).
    pub counts: [u32; SDS_LINK_STATUSES],
}

/// Which member of an `sds_link_message` is set.
#[allow(non_camel_case_types)]
pub type sds_link_message_kind = u32;
/// A start (doer to checker; nothing else is set).
pub const SDS_LINK_MESSAGE_START: sds_link_message_kind = 1;
/// A frame (doer to checker; nothing else is set).
pub const SDS_LINK_MESSAGE_FRAME: sds_link_message_kind = 2;
/// An end (doer to checker; nothing else is set).
pub const SDS_LINK_MESSAGE_END: sds_link_message_kind = 3;
/// An event: `event` is set.
pub const SDS_LINK_MESSAGE_EVENT: sds_link_message_kind = 4;
/// A status: `status` is set.
pub const SDS_LINK_MESSAGE_STATUS: sds_link_message_kind = 5;
/// A route summary: `summary` is set.
pub const SDS_LINK_MESSAGE_SUMMARY: sds_link_message_kind = 6;

/// One decoded message: `kind` says which member is set; the others are zero.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[allow(non_camel_case_types)]
pub struct sds_link_message {
    /// `SDS_LINK_MESSAGE_*`.
    pub kind: sds_link_message_kind,
    /// The message's E2E counter.
    pub counter: u16,
    /// Set when `kind == SDS_LINK_MESSAGE_EVENT`.
    pub event: sds_link_event,
    /// Set when `kind == SDS_LINK_MESSAGE_STATUS`.
    pub status: sds_link_status,
    /// Set when `kind == SDS_LINK_MESSAGE_SUMMARY`.
    pub summary: sds_link_summary,
}

fn to_c(counter: u16, m: &Message) -> sds_link_message {
    let mut out = sds_link_message {
        counter,
        ..sds_link_message::default()
    };
    match m {
        Message::Start(_) => out.kind = SDS_LINK_MESSAGE_START,
        Message::Frame(_) => out.kind = SDS_LINK_MESSAGE_FRAME,
        Message::End { .. } => out.kind = SDS_LINK_MESSAGE_END,
        Message::Event(t) => {
            out.kind = SDS_LINK_MESSAGE_EVENT;
            out.event.frame_counter = t.counter;
            match t.event {
                LinkEvent::Monitor(e) => {
                    out.event.kind = SDS_LINK_EVENT_MONITOR;
                    out.event.monitor = (&e).into();
                }
                LinkEvent::Segment { index } => {
                    out.event.kind = SDS_LINK_EVENT_SEGMENT;
                    out.event.value = index;
                }
                LinkEvent::LinkFault { bad } => {
                    out.event.kind = SDS_LINK_EVENT_LINK_FAULT;
                    out.event.value = bad;
                }
                LinkEvent::LinkRestored { bad } => {
                    out.event.kind = SDS_LINK_EVENT_LINK_RESTORED;
                    out.event.value = bad;
                }
            }
        }
        Message::Status(s) => {
            out.kind = SDS_LINK_MESSAGE_STATUS;
            out.status = s.into();
        }
        Message::Summary(s) => {
            out.kind = SDS_LINK_MESSAGE_SUMMARY;
            out.summary = sds_link_summary {
                route: (&s.route).into(),
                gaps: s.gaps,
                segments: s.segments,
                counts: counts(&s.counts),
            };
        }
    }
    out
}

/// Decodes one message as it came off the wire: `bytes[0 .. len]` are its COBS bytes, with or
/// without the 0x00 delimiter (split the stream at each 0x00). The end-to-end check (length,
/// data id, CRC) runs first; `*message` gets the message, or zero on failure.
///
/// Errors: `SDS_RESULT_NULL_POINTER`, `SDS_RESULT_MISALIGNED_POINTER`,
/// `SDS_RESULT_LINK_MESSAGE` (not one intact message of the link: what the checker counts as
/// `ERROR`).
///
/// ```c
/// sds_link_message msg;
/// if (sds_link_decode(bytes, n, &msg) == SDS_RESULT_OK && msg.kind == SDS_LINK_MESSAGE_EVENT &&
///     msg.event.kind == SDS_LINK_EVENT_LINK_FAULT) { /* the checker lost sight of the doer */ }
/// ```
///
/// # Safety
/// `bytes` is readable for `len` bytes (or NULL with `len` 0); `message` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn sds_link_decode(
    bytes: *const u8,
    len: usize,
    message: *mut sds_link_message,
) -> sds_result {
    guard(|| {
        if let Err(e) = usable(message) {
            return e;
        }
        // SAFETY: usable; the caller promises a writable sds_link_message.
        let out = unsafe { &mut *message };
        *out = sds_link_message::default();
        if bytes.is_null() && len > 0 {
            return sds_result::NullPointer;
        }
        let input = if len == 0 {
            &[][..]
        } else {
            // SAFETY: non-NULL and readable for len bytes (the caller's promise).
            unsafe { core::slice::from_raw_parts(bytes, len) }
        };
        // The delimiter is optional; a 0x00 before the end is not one message.
        let body = input.strip_suffix(&[0]).unwrap_or(input);
        if body.contains(&0) {
            return sds_result::LinkMessage;
        }
        let mut rx = Deframer::new();
        for &b in body {
            let _ = rx.push(b);
        }
        match rx.push(0) {
            Some(Ok(m)) => match link::decode(m) {
                Ok((h, m)) => {
                    *out = to_c(h.counter, &m);
                    sds_result::Ok
                }
                Err(_) => sds_result::LinkMessage,
            },
            _ => sds_result::LinkMessage,
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::sds_config_default;
    use std::vec::Vec;

    unsafe extern "C" fn collect(ctx: *mut c_void, bytes: *const u8, len: usize) {
        // SAFETY: ctx is the test's Vec; bytes valid for len during the call.
        let v = unsafe { &mut *ctx.cast::<Vec<u8>>() };
        v.extend_from_slice(unsafe { core::slice::from_raw_parts(bytes, len) });
    }

    fn decode_all(wire: &[u8]) -> Vec<sds_link_message> {
        wire.split_inclusive(|&b| b == 0)
            .map(|m| {
                let mut msg = sds_link_message::default();
                // SAFETY: valid slices and a local output.
                assert_eq!(
                    unsafe { sds_link_decode(m.as_ptr(), m.len(), &mut msg) },
                    sds_result::Ok
                );
                msg
            })
            .collect()
    }

    #[test]
    fn a_route_through_the_c_checker_gives_the_core_checker_s_answers() {
        let mut mem = core::mem::MaybeUninit::<sds_link_checker_storage>::zeroed();
        let k = mem.as_mut_ptr().cast::<sds_link_checker>();
        let lc = sds_link_config_default();
        let c = sds_config_default();
        let mut wire = Vec::new();
        let mut buf = [0u8; SDS_LINK_MAX_ENCODED];
        let mut n = 0usize;
        // SAFETY: every pointer is valid for the sizes given.
        unsafe {
            assert_eq!(
                sds_link_receive(k, buf.as_ptr(), 1, 0, Some(collect), core::ptr::null_mut()),
                sds_result::NotInitialized
            );
            assert_eq!(
                sds_link_checker_init(k, sds_link_checker_size() - 1, &lc),
                sds_result::BufferTooSmall
            );
            let bad = sds_link_config { window: 33, ..lc };
            assert_eq!(
                sds_link_checker_init(k, size_of::<sds_link_checker_storage>(), &bad),
                sds_result::LinkConfigWindow
            );
            assert_eq!(
                sds_link_checker_init(k, size_of::<sds_link_checker_storage>(), &lc),
                sds_result::Ok
            );
            assert_eq!(
                sds_link_encode_start(&c, 0, buf.as_mut_ptr(), 10, &mut n),
                sds_result::OutputTooSmall
            );
            assert_eq!(
                sds_link_encode_start(&c, 0, buf.as_mut_ptr(), buf.len(), &mut n),
                sds_result::Ok
            );
            wire.extend_from_slice(&buf[..n]);
            let mut f = sds_frame {
                speed: 8.0,
                ..sds_frame::default()
            };
            for counter in 0..40u16 {
                f.collisions.vehicle = u16::from(counter == 30);
                assert_eq!(
                    sds_link_encode_frame(&f, counter, buf.as_mut_ptr(), buf.len(), &mut n),
                    sds_result::Ok
                );
                assert_eq!(n, 47);
                wire.extend_from_slice(&buf[..n]);
            }
            // A corrupted copy of the next frame: ERROR, dropped.
            assert_eq!(
                sds_link_encode_frame(&f, 40, buf.as_mut_ptr(), buf.len(), &mut n),
                sds_result::Ok
            );
            buf[20] ^= 0x10;
            wire.extend_from_slice(&buf[..n]);
            assert_eq!(
                sds_link_encode_end(40, 0, buf.as_mut_ptr(), buf.len(), &mut n),
                sds_result::Ok
            );
            wire.extend_from_slice(&buf[..n]);
            let mut answers: Vec<u8> = Vec::new();
            let ctx = (&mut answers as *mut Vec<u8>).cast::<c_void>();
            assert_eq!(
                sds_link_receive(k, wire.as_ptr(), wire.len(), 0, Some(collect), ctx),
                sds_result::Ok
            );
            assert_eq!(
                sds_link_receive(k, wire.as_ptr(), 1, 0, None, ctx),
                sds_result::NullPointer
            );
            let mut s = sds_link_status::default();
            assert_eq!(sds_link_checker_status(k, &mut s), sds_result::Ok);
            assert_eq!(
                (s.valid, s.route, s.accepted),
                (true, SDS_LINK_ROUTE_FINISHED, 40)
            );
            assert_eq!(s.counts[SDS_LINK_STATUS_ERROR], 1);

            // The same bytes through the core's checker give the same answers.
            let mut core_k: Checker = Checker::new(LinkConfig::DEFAULT).unwrap();
            let mut want = Vec::new();
            core_k.receive(&wire, 0, &mut |b: &[u8]| want.extend_from_slice(b));
            assert_eq!(answers, want);
            let msgs = decode_all(&answers);
            let collision = msgs.iter().find(|m| {
                m.kind == SDS_LINK_MESSAGE_EVENT
                    && m.event.monitor.kind == crate::event::SDS_EVENT_COLLISION
            });
            assert_eq!(collision.map(|m| m.event.frame_counter), Some(30));
            let summary = msgs
                .iter()
                .find(|m| m.kind == SDS_LINK_MESSAGE_SUMMARY)
                .unwrap();
            assert_eq!(
                (summary.summary.route.frames, summary.summary.segments),
                (40, 1)
            );
            assert_eq!(summary.summary.counts[SDS_LINK_STATUS_OK], 40);
            assert_eq!(summary.summary.counts[SDS_LINK_STATUS_ERROR], 1);

            let mut msg = sds_link_message::default();
            assert_eq!(
                sds_link_decode(buf.as_ptr(), 3, &mut msg),
                sds_result::LinkMessage
            );
            assert_eq!(msg.kind, 0);
        }
    }
}
