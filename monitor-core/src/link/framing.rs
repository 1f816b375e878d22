//! Messages on a byte stream: each message is COBS-encoded (no 0x00 inside) and ends with one
//! 0x00 byte, so a receiver that lost bytes finds the next message at the next 0x00.
//!
//! The encoder is the `cobs` crate's (no_std, no allocation with its default features off, the
//! usual choice on embedded Rust). The receiving side decodes as the bytes arrive, in
//! [`Deframer::push`]: one pass instead of a second one over the buffer at the delimiter, and
//! no bounds check the optimiser cannot remove (the crate's in-place decoder kept three), so the
//! Cortex-M link checker's release build proves its receive path panic-free
//! (firmware-example/link-checker). The property tests hold it to the crate's encoder.

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
    /// The message decoded so far.
    buf: [u8; MAX_ENCODED],
    len: usize,
    /// Encoded bytes since the last delimiter.
    seen: usize,
    /// Data bytes left in the current COBS block (0: the next byte is a block's code).
    block_left: u8,
    /// The current block stands for its bytes and a 0x00 (its code was not 0xFF); the zero is
    /// written when another block follows, and is the delimiter itself otherwise.
    zero_after: bool,
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
            seen: 0,
            block_left: 0,
            zero_after: false,
        }
    }

    /// Forgets a partly received message.
    pub fn clear(&mut self) {
        self.len = 0;
        self.seen = 0;
        self.block_left = 0;
        self.zero_after = false;
    }

    fn put(&mut self, byte: u8) {
        // `seen` bounds `len` (a message never decodes longer than its encoding), so the slot
        // is always there; `get_mut` says so without a panicking branch.
        if let Some(slot) = self.buf.get_mut(self.len) {
            *slot = byte;
            self.len += 1;
        }
    }

    /// Takes one byte. At a delimiter, returns the decoded message (valid until the next call)
    /// or why the bytes before it are not one; two delimiters in a row are not a message.
    pub fn push(&mut self, byte: u8) -> Option<Result<&mut [u8], FramingError>> {
        if byte != 0 {
            self.seen = self.seen.saturating_add(1);
            if self.seen > MAX_ENCODED {
                return None; // too long: reported at the delimiter
            }
            if self.block_left == 0 {
                // A block's code: its data bytes follow, then (unless 0xFF) a zero.
                if self.zero_after {
                    self.put(0);
                }
                self.block_left = byte - 1;
                self.zero_after = byte != 0xFF;
            } else {
                self.put(byte);
                self.block_left -= 1;
            }
            return None;
        }
        let (len, seen, truncated) = (self.len, self.seen, self.block_left != 0);
        self.clear();
        if seen > MAX_ENCODED {
            return Some(Err(FramingError::TooLong));
        }
        if seen == 0 {
            return None;
        }
        if truncated {
            // The last block's code promised more bytes than came before the delimiter.
            return Some(Err(FramingError::Cobs));
        }
        Some(self.buf.get_mut(..len).ok_or(FramingError::TooLong))
    }
}
