//! A small reader of OMG CDR (XCDR1), the encoding of ROS 2 messages in MCAP (`cdr`): the
//! 4-byte encapsulation header, then little- or big-endian values aligned to their size,
//! counted from the end of the header. Only what the few message types of
//! [`super::messages`] need: f64, u32, i32, strings and sequences.
//!
//! ```
//! use monitor_host::input::mcap::cdr::Cdr;
//! // header (CDR_LE), u32 7, 4 bytes of padding, then an f64 aligned to 8 after the header.
//! let mut b = vec![0u8, 1, 0, 0, 7, 0, 0, 0, 0, 0, 0, 0];
//! b.extend_from_slice(&2.5f64.to_le_bytes());
//! let mut c = Cdr::new(&b)?;
//! assert_eq!((c.u32()?, c.f64()?), (7, 2.5));
//! # Ok::<(), monitor_host::input::mcap::cdr::CdrError>(())
//! ```

/// Why a message's bytes are not the CDR of its type.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum CdrError {
    /// Fewer than 4 bytes, or an encapsulation other than CDR_BE / CDR_LE (`00 00` / `00 01`).
    #[error("not CDR: encapsulation header {:02x?} (expected 00 00 or 00 01)", &first[..(*len).min(4)])]
    Header {
        /// The first bytes of the message.
        first: [u8; 4],
        /// The message's length.
        len: usize,
    },
    /// The message ends before the value at this offset.
    #[error("message ends at byte {len}, inside a value at byte {at}")]
    Short {
        /// Offset of the value (from the start of the message).
        at: usize,
        /// Length of the message.
        len: usize,
    },
    /// A string that is not NUL-terminated UTF-8.
    #[error("string at byte {0} is not NUL-terminated UTF-8")]
    BadString(usize),
}

/// A cursor over one CDR message.
#[derive(Debug, Clone)]
pub struct Cdr<'a> {
    bytes: &'a [u8],
    pos: usize,
    little: bool,
}

/// Offset of the first value: alignment counts from here.
const HEADER: usize = 4;

impl<'a> Cdr<'a> {
    /// A cursor after the encapsulation header of `bytes`.
    ///
    /// # Errors
    /// [`CdrError::Header`] when the header is missing or not plain CDR.
    pub fn new(bytes: &'a [u8]) -> Result<Self, CdrError> {
        let mut first = [0u8; 4];
        for (f, b) in first.iter_mut().zip(bytes) {
            *f = *b;
        }
        let bad = CdrError::Header {
            first,
            len: bytes.len(),
        };
        let little = match bytes.get(..2) {
            Some([0, 1]) => true,
            Some([0, 0]) => false,
            _ => return Err(bad),
        };
        if bytes.len() < HEADER {
            return Err(bad);
        }
        Ok(Cdr {
            bytes,
            pos: HEADER,
            little,
        })
    }

    fn take<const N: usize>(&mut self) -> Result<[u8; N], CdrError> {
        // Values are aligned to their size, from the end of the header.
        let pad = (N - (self.pos - HEADER) % N) % N;
        let at = self.pos + pad;
        let b = self
            .bytes
            .get(at..at + N)
            .and_then(|s| <[u8; N]>::try_from(s).ok())
            .ok_or(CdrError::Short {
                at,
                len: self.bytes.len(),
            })?;
        self.pos = at + N;
        Ok(b)
    }

    /// An unsigned 32-bit integer.
    ///
    /// # Errors
    /// [`CdrError::Short`].
    pub fn u32(&mut self) -> Result<u32, CdrError> {
        let b = self.take::<4>()?;
        Ok(if self.little {
            u32::from_le_bytes(b)
        } else {
            u32::from_be_bytes(b)
        })
    }

    /// A signed 32-bit integer.
    ///
    /// # Errors
    /// [`CdrError::Short`].
    pub fn i32(&mut self) -> Result<i32, CdrError> {
        self.u32().map(|u| u as i32)
    }

    /// A 64-bit float.
    ///
    /// # Errors
    /// [`CdrError::Short`].
    pub fn f64(&mut self) -> Result<f64, CdrError> {
        let b = self.take::<8>()?;
        Ok(if self.little {
            f64::from_le_bytes(b)
        } else {
            f64::from_be_bytes(b)
        })
    }

    /// `n` 64-bit floats (a fixed array such as a covariance), skipped or read.
    ///
    /// # Errors
    /// [`CdrError::Short`].
    pub fn f64s<const N: usize>(&mut self) -> Result<[f64; N], CdrError> {
        let mut out = [0.0; N];
        for v in &mut out {
            *v = self.f64()?;
        }
        Ok(out)
    }

    /// A string: u32 length (with its NUL), the bytes, the NUL.
    ///
    /// # Errors
    /// [`CdrError::Short`], [`CdrError::BadString`].
    pub fn string(&mut self) -> Result<&'a str, CdrError> {
        let n = self.u32()? as usize;
        let at = self.pos;
        let s = at
            .checked_add(n)
            .and_then(|end| self.bytes.get(at..end))
            .ok_or(CdrError::Short {
                at,
                len: self.bytes.len(),
            })?;
        self.pos = at + n;
        match s.split_last() {
            None => Ok(""),
            Some((0, text)) => std::str::from_utf8(text).map_err(|_| CdrError::BadString(at)),
            Some(_) => Err(CdrError::BadString(at)),
        }
    }

    /// The length of a sequence that follows, checked against the bytes left (each element
    /// takes at least `min_size` bytes), so that a corrupt count cannot ask for a huge buffer.
    ///
    /// # Errors
    /// [`CdrError::Short`] when the sequence cannot fit.
    pub fn sequence_len(&mut self, min_size: usize) -> Result<usize, CdrError> {
        let n = self.u32()? as usize;
        let left = self.bytes.len().saturating_sub(self.pos);
        if n.saturating_mul(min_size.max(1)) > left {
            return Err(CdrError::Short {
                at: self.pos,
                len: self.bytes.len(),
            });
        }
        Ok(n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn big_endian_and_alignment_after_a_string() {
        // CDR_BE, string "ab" (len 3 with NUL), pad to 8, f64 1.5.
        let mut b = vec![0u8, 0, 0, 0, 0, 0, 0, 3, b'a', b'b', 0];
        b.resize(4 + 8, 0);
        b.extend_from_slice(&1.5f64.to_be_bytes());
        let mut c = Cdr::new(&b).unwrap();
        assert_eq!(c.string().unwrap(), "ab");
        assert_eq!(c.f64().unwrap(), 1.5);
        assert!(matches!(c.f64(), Err(CdrError::Short { .. })));
    }

    #[test]
    fn refuses_other_encapsulations_and_huge_counts() {
        assert!(Cdr::new(&[0, 3, 0, 0]).is_err());
        assert!(Cdr::new(&[]).is_err());
        let mut c = Cdr::new(&[0, 1, 0, 0, 255, 255, 255, 255]).unwrap();
        assert!(c.sequence_len(8).is_err());
    }
}
