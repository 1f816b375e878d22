//! Messages on a byte stream: each message is COBS-encoded (no 0x00 inside) and ends with one
//! 0x00 byte, so a receiver that lost bytes finds the next message at the next 0x00.
//!
//! COBS comes from the `cobs` crate (no_std, no allocation with its default features off; it
//! encodes into and decodes in a caller's slice, returning errors rather than panicking), the
//! usual choice on embedded Rust, so the checker needs no own encoder.

use crate::link::payload::MAX_MESSAGE;

/// Bytes of the largest message on the stream: COBS adds one byte per 254 and the delimiter.
pub const MAX_ENCODED: usize = MAX_MESSAGE + MAX_MESSAGE / 254 + 2;

/// Why bytes between two delimiters are not a message (their check status is `ERROR`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum FramingError {
    /// More bytes than the largest message before a delimiter (they were dropped).
    TooLong,
    /// Not valid COBS.
    Cobs,
}

/// COBS-encodes `message` into `out` and appends the 0x00 delimiter; returns the bytes written,
/// or `None` when `out` is too small.
///
/// ```
/// let mut out = [0u8; 8];
/// let n = monitor_core::link::framing::frame(&[0x11, 0x00, 0x22], &mut out).unwrap();
/// assert_eq!(&out[..n], &[0x02, 0x11, 0x02, 0x22, 0x00]);
/// ```
pub fn frame(message: &[u8], out: &mut [u8]) -> Option<usize> {
    let n = cobs::try_encode(message, out).ok()?;
    *out.get_mut(n)? = 0;
    Some(n + 1)
}

/// The receiving side: collects bytes up to a delimiter in a fixed buffer and decodes them.
/// Memory is fixed ([`MAX_ENCODED`] bytes); a stream of random bytes or a sender that never
/// sends a delimiter costs nothing more than an error per delimiter.
///
/// ```
/// use monitor_core::link::{Deframer, FramingError};
/// let mut rx = Deframer::new();
/// let mut got = Vec::new();
/// for b in [0x02, 0x11, 0x02, 0x22, 0x00, 0x05, 0x00] {
///     if let Some(r) = rx.push(b) {
///         got.push(r.map(|m| m.to_vec()));
///     }
/// }
/// assert_eq!(got, [Ok(vec![0x11, 0x00, 0x22]), Err(FramingError::Cobs)]);
/// ```
#[derive(Clone, Debug)]
pub struct Deframer {
    buf: [u8; MAX_ENCODED],
    len: usize,
    overflow: bool,
}

impl Default for Deframer {
    fn default() -> Self {
        Self::new()
    }
}

impl Deframer {
    /// Empty.
    pub const fn new() -> Self {
        Deframer {
            buf: [0; MAX_ENCODED],
            len: 0,
            overflow: false,
        }
    }

    /// Forgets a partly received message.
    pub fn clear(&mut self) {
        self.len = 0;
        self.overflow = false;
    }

    /// Takes one byte. At a delimiter, returns the decoded message (valid until the next call)
    /// or why the bytes before it are not one; two delimiters in a row are not a message.
    pub fn push(&mut self, byte: u8) -> Option<Result<&mut [u8], FramingError>> {
        if byte != 0 {
            match self.buf.get_mut(self.len) {
                Some(slot) if !self.overflow => {
                    *slot = byte;
                    self.len += 1;
                }
                _ => self.overflow = true,
            }
            return None;
        }
        let (len, overflow) = (self.len, self.overflow);
        self.clear();
        if overflow {
            return Some(Err(FramingError::TooLong));
        }
        if len == 0 {
            return None;
        }
        let encoded = &mut self.buf[..len];
        match cobs::decode_in_place(encoded) {
            Ok(n) => Some(Ok(&mut self.buf[..n])),
            Err(_) => Some(Err(FramingError::Cobs)),
        }
    }
}
