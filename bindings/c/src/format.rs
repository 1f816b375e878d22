//! Numbers as text: the shortest decimal form that reads back to the same bits (Ryū), the form
//! the host tool's JSON writes, so C programs can print lines byte-identical to the Rust tools'.

use core::ffi::c_char;

use crate::result::sds_result;
use crate::{guard, usable};

/// Bytes `sds_format_f32` / `sds_format_f64` may need, the terminating NUL included.
pub const SDS_NUMBER_TEXT_MAX: usize = 32;

/// Writes `text` and a NUL into `buf[0 .. len]`, its length (without the NUL) into `*written`.
///
/// # Safety
/// `buf` is NULL or writable for `len` bytes; `written` is NULL or writable.
unsafe fn put(text: &str, buf: *mut c_char, len: usize, written: *mut usize) -> sds_result {
    if buf.is_null() {
        return sds_result::NullPointer;
    }
    if let Err(e) = usable(written) {
        return e;
    }
    let n = text.len();
    if n >= len {
        return sds_result::OutputTooSmall;
    }
    // SAFETY: buf is non-NULL and writable for len > n bytes (the caller's promise), and text
    // is a distinct Rust buffer, so the ranges do not overlap.
    unsafe {
        core::ptr::copy_nonoverlapping(text.as_ptr(), buf.cast::<u8>(), n);
        buf.add(n).write(0);
        written.write(n);
    }
    sds_result::Ok
}

/// Formats `value` in the shortest form that reads back to the same `float` ("0.5", "1.0",
/// "1e-7"; "NaN", "inf", "-inf" when not finite), NUL-terminated, into `buf` of `len` bytes;
/// `*written` gets the length without the NUL. `SDS_RESULT_OUTPUT_TOO_SMALL` (nothing written)
/// when it does not fit; `SDS_NUMBER_TEXT_MAX` bytes always suffice.
///
/// ```c
/// char text[SDS_NUMBER_TEXT_MAX];
/// size_t n;
/// sds_format_f32(0.1f, text, sizeof text, &n);   /* "0.1", n == 3 */
/// ```
///
/// # Safety
/// `buf` is NULL or writable for `len` bytes; `written` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn sds_format_f32(
    value: f32,
    buf: *mut c_char,
    len: usize,
    written: *mut usize,
) -> sds_result {
    guard(|| {
        let mut b = ryu::Buffer::new();
        // SAFETY: forwarded from the caller.
        unsafe { put(b.format(value), buf, len, written) }
    })
}

/// `sds_format_f32` for a `double` (the scores).
///
/// ```c
/// char text[SDS_NUMBER_TEXT_MAX];
/// size_t n;
/// sds_format_f64(out.ds_safe, text, sizeof text, &n);
/// ```
///
/// # Safety
/// `buf` is NULL or writable for `len` bytes; `written` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn sds_format_f64(
    value: f64,
    buf: *mut c_char,
    len: usize,
    written: *mut usize,
) -> sds_result {
    guard(|| {
        let mut b = ryu::Buffer::new();
        // SAFETY: forwarded from the caller.
        unsafe { put(b.format(value), buf, len, written) }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn f32_text(v: f32, len: usize) -> Result<std::string::String, sds_result> {
        let mut buf = [0x55 as c_char; SDS_NUMBER_TEXT_MAX];
        let mut n = 0usize;
        // SAFETY: buf is writable for min(len, its size) bytes.
        let r = unsafe { sds_format_f32(v, buf.as_mut_ptr(), len.min(buf.len()), &mut n) };
        if r != sds_result::Ok {
            return Err(r);
        }
        assert_eq!(buf[n], 0, "NUL-terminated");
        let bytes: std::vec::Vec<u8> = buf[..n].iter().map(|&c| c as u8).collect();
        Ok(std::string::String::from_utf8(bytes).unwrap())
    }

    #[test]
    fn shortest_round_trip_forms() {
        assert_eq!(f32_text(0.5, 32).unwrap(), "0.5");
        assert_eq!(f32_text(1.0, 32).unwrap(), "1.0");
        assert_eq!(f32_text(1e-7, 32).unwrap(), "1e-7");
        assert_eq!(f32_text(f32::NAN, 32).unwrap(), "NaN");
        let x = 0.1f32 + 0.2f32;
        assert_eq!(
            f32_text(x, 32).unwrap().parse::<f32>().unwrap().to_bits(),
            x.to_bits()
        );
        // Worst case fits in SDS_NUMBER_TEXT_MAX.
        assert!(f32_text(-1.1754942e-38, 32).is_ok());
        let mut buf = [0 as c_char; SDS_NUMBER_TEXT_MAX];
        let mut n = 0;
        // SAFETY: valid pointers to locals.
        let r = unsafe {
            sds_format_f64(
                -2.2250738585072014e-308,
                buf.as_mut_ptr(),
                buf.len(),
                &mut n,
            )
        };
        assert_eq!(r, sds_result::Ok);
    }

    #[test]
    fn too_small_and_null() {
        assert_eq!(f32_text(0.5, 3), Err(sds_result::OutputTooSmall)); // "0.5" + NUL needs 4
        assert_eq!(f32_text(0.5, 4).unwrap(), "0.5");
        let mut n = 0;
        // SAFETY: NULL is refused before any access.
        let r = unsafe { sds_format_f32(1.0, core::ptr::null_mut(), 8, &mut n) };
        assert_eq!(r, sds_result::NullPointer);
    }
}
