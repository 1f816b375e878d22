//! `sds_monitor`: the streaming monitor of one route, in memory the caller owns.

use core::mem::{align_of, size_of};

use monitor_core::{Frame, Monitor};

use crate::config::sds_config;
use crate::event::sds_events;
use crate::frame::sds_frame;
use crate::result::{code, sds_result};
use crate::summary::sds_summary;
use crate::{guard, usable};

/// Marks an initialised monitor, so that a zeroed or never-initialised buffer is refused.
const MAGIC: u32 = 0x5344_534D; // "SDSM"

/// The monitor of one route (opaque). It lives in a buffer the caller owns: at least
/// `sds_monitor_size()` bytes aligned to `sds_monitor_align()`, for example an
/// `sds_monitor_storage`. Nothing is allocated and nothing needs freeing.
#[allow(non_camel_case_types)]
pub struct sds_monitor {
    magic: u32,
    monitor: Monitor,
}

/// 64-bit words of `sds_monitor_storage`.
pub const SDS_MONITOR_STORAGE_WORDS: usize = 84;

/// Memory for one monitor with the right size and alignment for every target, usable as a
/// `static` or on the stack: `sds_monitor_storage mem; sds_monitor *m = (sds_monitor *)&mem;`.
/// It is larger than `sds_monitor_size()` on 32-bit targets.
#[repr(C)]
#[allow(non_camel_case_types)]
pub struct sds_monitor_storage {
    /// Opaque.
    pub _words: [u64; SDS_MONITOR_STORAGE_WORDS],
}

// The storage type must hold the monitor on every target (a bigger core is a compile error
// here: raise SDS_MONITOR_STORAGE_WORDS, an ABI change).
const _: () = assert!(size_of::<sds_monitor>() <= size_of::<sds_monitor_storage>());
const _: () = assert!(align_of::<sds_monitor>() <= align_of::<sds_monitor_storage>());

/// Bytes a monitor needs (at most `sizeof(sds_monitor_storage)`).
///
/// ```c
/// void *buf = aligned_alloc(sds_monitor_align(), 1024);   /* 1024 >= sds_monitor_size() */
/// ```
#[no_mangle]
pub extern "C" fn sds_monitor_size() -> usize {
    size_of::<sds_monitor>()
}

/// Alignment a monitor's buffer needs, in bytes.
///
/// ```c
/// assert(sds_monitor_align() <= _Alignof(sds_monitor_storage));   /* C11 */
/// ```
#[no_mangle]
pub extern "C" fn sds_monitor_align() -> usize {
    align_of::<sds_monitor>()
}

/// Refuses a NULL, misaligned or never-initialised `m`.
///
/// # Safety
/// `m` is NULL or points to at least `sds_monitor_size()` readable bytes (normally a buffer
/// passed to a successful `sds_monitor_init`; other memory is refused by its magic number).
unsafe fn check(m: *const sds_monitor) -> Result<(), sds_result> {
    if m.is_null() {
        return Err(sds_result::NullPointer);
    }
    if !m.is_aligned() {
        return Err(sds_result::BufferMisaligned);
    }
    // SAFETY: non-NULL, aligned and readable (the caller's promise); any bits are a valid u32.
    let magic = unsafe { core::ptr::addr_of!((*m).magic).read() };
    if magic != MAGIC {
        return Err(sds_result::NotInitialized);
    }
    Ok(())
}

/// The initialised monitor behind `m`, to change it.
///
/// # Safety
/// As [`check`], and nothing else accesses the monitor while the reference lives.
unsafe fn state_mut<'a>(m: *mut sds_monitor) -> Result<&'a mut Monitor, sds_result> {
    // SAFETY: forwarded from the caller.
    unsafe { check(m) }?;
    // SAFETY: the magic says sds_monitor_init wrote a valid monitor here; the caller promises
    // exclusive access for the duration of the call.
    Ok(unsafe { &mut (*m).monitor })
}

/// The initialised monitor behind `m`, to read it.
///
/// # Safety
/// As [`check`], and nothing writes to the monitor while the reference lives.
unsafe fn state_ref<'a>(m: *const sds_monitor) -> Result<&'a Monitor, sds_result> {
    // SAFETY: forwarded from the caller.
    unsafe { check(m) }?;
    // SAFETY: the magic says sds_monitor_init wrote a valid monitor here.
    Ok(unsafe { &(*m).monitor })
}

/// Initialises a monitor for one route in the caller's buffer `monitor` of `len` bytes, with
/// the configuration `config` (checked as `sds_config_validate` does). On failure the buffer is
/// left untouched. Re-initialising a monitor starts afresh with the new configuration.
///
/// Errors: `SDS_RESULT_NULL_POINTER`, `SDS_RESULT_BUFFER_TOO_SMALL` (`len <
/// sds_monitor_size()`), `SDS_RESULT_BUFFER_MISALIGNED`, `SDS_RESULT_MISALIGNED_POINTER`
/// (`config`), `SDS_RESULT_CONFIG_*`.
///
/// ```c
/// static sds_monitor_storage mem;                 /* or any suitably aligned buffer */
/// sds_monitor *m = (sds_monitor *)&mem;
/// sds_config c = sds_config_default();
/// sds_result r = sds_monitor_init(m, sizeof mem, &c);   /* SDS_RESULT_OK */
/// ```
///
/// # Safety
/// `monitor` is NULL or writable for `len` bytes, and not used by anyone else during the call;
/// `config` is NULL or points to a readable `sds_config`.
#[no_mangle]
pub unsafe extern "C" fn sds_monitor_init(
    monitor: *mut sds_monitor,
    len: usize,
    config: *const sds_config,
) -> sds_result {
    guard(|| {
        if monitor.is_null() {
            return sds_result::NullPointer;
        }
        if let Err(e) = usable(config) {
            return e;
        }
        if len < size_of::<sds_monitor>() {
            return sds_result::BufferTooSmall;
        }
        if !monitor.is_aligned() {
            return sds_result::BufferMisaligned;
        }
        // SAFETY: usable (non-NULL, aligned); the caller promises a readable sds_config, and
        // any bits of its plain numeric fields are valid.
        let config = unsafe { config.read() };
        let m = match config
            .to_core()
            .and_then(|c| Monitor::new(c).map_err(Into::into))
        {
            Ok(m) => m,
            Err(e) => return e,
        };
        // SAFETY: non-NULL, aligned, writable for len >= size_of::<sds_monitor>() bytes. The
        // old contents (plain data, nothing to drop) are overwritten, not read.
        unsafe {
            monitor.write(sds_monitor {
                magic: MAGIC,
                monitor: m,
            })
        };
        sds_result::Ok
    })
}

/// Pushes one frame. `*events` gets the events it caused (often none), in order. On failure
/// the monitor is unchanged (skip the frame or finish the route) and `events->len` is 0.
///
/// Errors: `SDS_RESULT_NULL_POINTER`, `SDS_RESULT_MISALIGNED_POINTER`,
/// `SDS_RESULT_NOT_INITIALIZED`, `SDS_RESULT_BUFFER_MISALIGNED`, `SDS_RESULT_FRAME_*` (a NaN,
/// infinite or negative field), `SDS_RESULT_FINISHED`, `SDS_RESULT_TOO_MANY_FRAMES`.
///
/// ```c
/// sds_frame f = {0};
/// f.speed = 8.0f;
/// f.collisions.vehicle = 1;
/// sds_events ev;
/// if (sds_monitor_push(m, &f, &ev) == SDS_RESULT_OK && ev.len > 0 &&
///     ev.events[0].kind == SDS_EVENT_COLLISION && ev.events[0].collision.nodecel) {
///   /* a collision without braking before it */
/// }
/// ```
///
/// # Safety
/// `monitor` is NULL or an initialised monitor nobody else uses during the call; `frame` is
/// NULL or readable; `events` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn sds_monitor_push(
    monitor: *mut sds_monitor,
    frame: *const sds_frame,
    events: *mut sds_events,
) -> sds_result {
    guard(|| {
        if let Err(e) = usable(events) {
            return e;
        }
        // SAFETY: usable; the caller promises a writable sds_events that nothing else uses.
        let events = unsafe { &mut *events };
        if let Err(e) = usable(frame) {
            *events = sds_events::default();
            return e;
        }
        // SAFETY: the caller's promise on `monitor`.
        let m = match unsafe { state_mut(monitor) } {
            Ok(m) => m,
            Err(e) => {
                *events = sds_events::default();
                return e;
            }
        };
        // SAFETY: usable; the caller promises a readable sds_frame.
        let frame = Frame::from(unsafe { &*frame });
        // Read the events where push left them: moving them out of the Result costs two
        // 64-byte unaligned copies on Cortex-M.
        let pushed = m.push(&frame);
        match &pushed {
            Ok(ev) => {
                events.set(ev);
                sds_result::Ok
            }
            Err(e) => {
                *events = sds_events::default();
                (*e).into()
            }
        }
    })
}

/// Ends the route: `*events` gets the events of its end (the short route's comfort chunk, the
/// trailing lateral chunk) and `*summary` the route's summary. A second call returns
/// `SDS_RESULT_FINISHED`; `sds_monitor_reset` starts the next route.
///
/// ```c
/// sds_events ev;
/// sds_summary s;
/// if (sds_monitor_finish(m, &ev, &s) == SDS_RESULT_OK) {
///   printf("%u frames, %u collisions without braking\n", s.frames, s.collisions.nodecel);
/// }
/// sds_monitor_reset(m);                           /* the next route */
/// ```
///
/// # Safety
/// `monitor` is NULL or an initialised monitor nobody else uses during the call; `events` and
/// `summary` are NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn sds_monitor_finish(
    monitor: *mut sds_monitor,
    events: *mut sds_events,
    summary: *mut sds_summary,
) -> sds_result {
    guard(|| {
        if let Err(e) = usable(events) {
            return e;
        }
        // SAFETY: usable; the caller promises a writable sds_events that nothing else uses.
        let events = unsafe { &mut *events };
        let r = (|| {
            usable(summary)?;
            // SAFETY: the caller's promise on `monitor`.
            let m = unsafe { state_mut(monitor) }?;
            let done = m.finish()?;
            events.set(&done.events);
            // SAFETY: usable; the caller promises a writable sds_summary.
            unsafe { summary.write((&done.summary).into()) };
            Ok(())
        })();
        if r.is_err() {
            *events = sds_events::default();
        }
        code(r)
    })
}

/// Starts a new route with the same configuration (after `sds_monitor_finish`, or to abandon
/// the current route).
///
/// ```c
/// sds_monitor_reset(m);   /* SDS_RESULT_OK; the counts start again from zero */
/// ```
///
/// # Safety
/// `monitor` is NULL or an initialised monitor nobody else uses during the call.
#[no_mangle]
pub unsafe extern "C" fn sds_monitor_reset(monitor: *mut sds_monitor) -> sds_result {
    guard(|| {
        // SAFETY: the caller's promise on `monitor`.
        match unsafe { state_mut(monitor) } {
            Ok(m) => {
                m.reset();
                sds_result::Ok
            }
            Err(e) => e,
        }
    })
}

/// The counts so far into `*summary` (final after `sds_monitor_finish`).
///
/// ```c
/// sds_summary s;
/// sds_monitor_summary(m, &s);   /* s.frames: frames pushed so far */
/// ```
///
/// # Safety
/// `monitor` is NULL or an initialised monitor nobody writes to during the call; `summary` is
/// NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn sds_monitor_summary(
    monitor: *const sds_monitor,
    summary: *mut sds_summary,
) -> sds_result {
    guard(|| {
        code((|| {
            usable(summary)?;
            // SAFETY: the caller's promise on `monitor`.
            let m = unsafe { state_ref(monitor) }?;
            // SAFETY: usable; the caller promises a writable sds_summary.
            unsafe { summary.write(m.summary().into()) };
            Ok(())
        })())
    })
}

/// The configuration in use into `*config`.
///
/// ```c
/// sds_config c;
/// sds_monitor_config(m, &c);   /* c.chunk_len == 20 with the defaults */
/// ```
///
/// # Safety
/// `monitor` is NULL or an initialised monitor nobody writes to during the call; `config` is
/// NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn sds_monitor_config(
    monitor: *const sds_monitor,
    config: *mut sds_config,
) -> sds_result {
    guard(|| {
        code((|| {
            usable(config)?;
            // SAFETY: the caller's promise on `monitor`.
            let m = unsafe { state_ref(monitor) }?;
            // SAFETY: usable; the caller promises a writable sds_config.
            unsafe { config.write((*m.config()).into()) };
            Ok(())
        })())
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::sds_config_default;

    #[test]
    fn init_checks_buffer_and_config() {
        let mut mem = core::mem::MaybeUninit::<sds_monitor_storage>::zeroed();
        let m = mem.as_mut_ptr().cast::<sds_monitor>();
        let size = size_of::<sds_monitor_storage>();
        let mut c = sds_config_default();
        let (mut ev, mut s) = (sds_events::default(), sds_summary::default());
        let f = sds_frame::default();
        // SAFETY: every pointer is NULL or valid for the sizes given.
        unsafe {
            assert_eq!(sds_monitor_push(m, &f, &mut ev), sds_result::NotInitialized);
            assert_eq!(
                sds_monitor_init(m, sds_monitor_size() - 1, &c),
                sds_result::BufferTooSmall
            );
            // Never written: the alignment check comes first.
            let odd = mem.as_mut_ptr().cast::<u8>().add(1).cast::<sds_monitor>();
            assert_eq!(
                sds_monitor_init(odd, sds_monitor_size(), &c),
                sds_result::BufferMisaligned
            );
            c.decel_window = 21;
            assert_eq!(sds_monitor_init(m, size, &c), sds_result::ConfigDecelWindow);
            c = sds_config_default();
            assert_eq!(sds_monitor_init(m, size, &c), sds_result::Ok);
            assert_eq!(sds_monitor_push(m, &f, &mut ev), sds_result::Ok);
            assert_eq!(sds_monitor_finish(m, &mut ev, &mut s), sds_result::Ok);
            assert_eq!(s.frames, 1);
            assert_eq!(sds_monitor_push(m, &f, &mut ev), sds_result::Finished);
            assert_eq!(sds_monitor_reset(m), sds_result::Ok);
            assert_eq!(sds_monitor_push(m, &f, &mut ev), sds_result::Ok);
        }
    }
}
