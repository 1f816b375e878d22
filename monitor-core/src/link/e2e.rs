//! The end-to-end header of every link message, as AUTOSAR's E2E Profile 4 lays it out and
//! checks it: big-endian `length` u16 (bytes of the whole message), `counter` u16, `data_id`
//! u32, `crc` u32, then the payload.
//!
//! The CRC is CRC-32/AUTOSAR (polynomial 0xF4ACFB13, init 0xFFFFFFFF, reflected in and out,
//! xorout 0xFFFFFFFF) over the whole message with the `crc` field left out: the first 8 bytes,
//! then the payload. It comes from the `crc` crate (no_std, no allocation, `CRC_32_AUTOSAR` from
//! its catalogue, checked against the catalogue's check value below), rather than an own table:
//! the polynomial's table is the part one gets wrong, and the crate is widely used and tested.
//! Its Hamming distance over messages of this size catches every burst of up to 32 bits and
//! every error of up to 5 bits, so every single-byte corruption (the property tests try them).

use crc::{Crc, Table, CRC_32_AUTOSAR};

/// Bytes of the header: length 2, counter 2, data id 4, CRC 4.
pub const HEADER_LEN: usize = 12;

/// CRC-32/AUTOSAR, byte-wise with one 256-entry table (1 KiB of flash). The `crc` crate's
/// `Table<16>` is slice-by-16, sixteen such tables (16 KiB): faster on long buffers, but a link
/// message is at most 116 bytes, and on the Cortex-M4F checker it was most of the image's
/// read-only data (docs/FIRMWARE.md).
const CRC: Crc<u32, Table<1>> = Crc::<u32, Table<1>>::new(&CRC_32_AUTOSAR);

/// The fields of a message's header.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Header {
    /// Bytes of the whole message, header included.
    pub length: u16,
    /// +1 per message of this data id, wrapping.
    pub counter: u16,
    /// What the payload is ([`crate::link::DATA_FRAME`] etc.).
    pub data_id: u32,
    /// CRC-32/AUTOSAR of the message without this field.
    pub crc: u32,
}

/// The CRC-32/AUTOSAR of `message` with its bytes 8..12 (the `crc` field) left out.
///
/// ```
/// // The catalogue's check value: CRC-32/AUTOSAR of "123456789" is 0x1697D06A.
/// let mut m = [0u8; 21];
/// m[..8].copy_from_slice(b"12345678");
/// m[12] = b'9';
/// assert_eq!(monitor_core::link::e2e::crc_of(&m[..13]), 0x1697_D06A);
/// ```
pub fn crc_of(message: &[u8]) -> u32 {
    let mut digest = CRC.digest();
    digest.update(message.get(..8).unwrap_or(message));
    digest.update(message.get(HEADER_LEN..).unwrap_or(&[]));
    digest.finalize()
}

/// Writes the header of a message of `message.len()` bytes (the payload already in place after
/// the header) and its CRC. `message` must be `HEADER_LEN..=u16::MAX` bytes; a shorter or
/// longer one is left as it is and `false` is returned.
///
/// ```
/// use monitor_core::link::e2e::{check, protect, HEADER_LEN};
/// let mut m = [0u8; HEADER_LEN + 3];
/// m[HEADER_LEN..].copy_from_slice(&[1, 2, 3]);
/// assert!(protect(&mut m, 7, 0x5344_5302));
/// let h = check(&m).unwrap();
/// assert_eq!((h.length, h.counter, h.data_id), (15, 7, 0x5344_5302));
/// ```
pub fn protect(message: &mut [u8], counter: u16, data_id: u32) -> bool {
    let Ok(length) = u16::try_from(message.len()) else {
        return false;
    };
    if message.len() < HEADER_LEN {
        return false;
    }
    message[0..2].copy_from_slice(&length.to_be_bytes());
    message[2..4].copy_from_slice(&counter.to_be_bytes());
    message[4..8].copy_from_slice(&data_id.to_be_bytes());
    let crc = crc_of(message);
    message[8..12].copy_from_slice(&crc.to_be_bytes());
    true
}

/// Why a message failed its end-to-end check (its check status is `ERROR`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum E2eError {
    /// Shorter than a header.
    Short,
    /// The `length` field is not the message's length.
    Length,
    /// The CRC does not match.
    Crc,
}

/// Reads and checks a message's header: the length field against the message's length, then the
/// CRC. The data id and the payload's layout are the caller's to check.
///
/// # Errors
/// [`E2eError`].
pub fn check(message: &[u8]) -> Result<Header, E2eError> {
    let (Some(h), true) = (message.get(..HEADER_LEN), message.len() >= HEADER_LEN) else {
        return Err(E2eError::Short);
    };
    let header = Header {
        length: u16::from_be_bytes([h[0], h[1]]),
        counter: u16::from_be_bytes([h[2], h[3]]),
        data_id: u32::from_be_bytes([h[4], h[5], h[6], h[7]]),
        crc: u32::from_be_bytes([h[8], h[9], h[10], h[11]]),
    };
    if usize::from(header.length) != message.len() {
        return Err(E2eError::Length);
    }
    if crc_of(message) != header.crc {
        return Err(E2eError::Crc);
    }
    Ok(header)
}
