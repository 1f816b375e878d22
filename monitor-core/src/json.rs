//! JSON without a heap (serde-json-core): decode a frame, encode events and summaries.

use serde::Serialize;

use crate::error::FrameError;
use crate::frame::Frame;

/// Why JSON could not be decoded or encoded.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum JsonError {
    /// The bytes are not a JSON frame (syntax, types or missing fields).
    Syntax,
    /// The frame decoded but is invalid.
    Frame(FrameError),
    /// The output buffer is too small.
    BufferFull,
}

impl core::fmt::Display for JsonError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            JsonError::Syntax => f.write_str("not a JSON frame"),
            JsonError::Frame(e) => write!(f, "invalid frame: {e}"),
            JsonError::BufferFull => f.write_str("output buffer too small"),
        }
    }
}

impl core::error::Error for JsonError {}

/// Decodes and validates one frame.
///
/// ```
/// let f = monitor_core::json::decode_frame(
///     br#"{"a_lon":-1.5,"a_lat":0.25,"a_mag":1.6,"yaw_rate":2.0,"speed":7.0,
///          "lat_err":null,"collisions":{"vehicle":1}}"#).unwrap();
/// assert_eq!(f.a_lon, -1.5);
/// assert_eq!(f.lat_err, None);
/// assert_eq!(f.collisions.vehicle, 1);
/// ```
pub fn decode_frame(bytes: &[u8]) -> Result<Frame, JsonError> {
    let (frame, _) = serde_json_core::from_slice::<Frame>(bytes).map_err(|_| JsonError::Syntax)?;
    frame.validate().map_err(JsonError::Frame)?;
    Ok(frame)
}

/// Encodes any public type (an [`crate::Event`], a [`crate::RouteSummary`], a frame) into `buf`;
/// returns the bytes written. Floats are written in their shortest round-trip form, so equal
/// bits give equal bytes on every target.
///
/// ```
/// let mut buf = [0u8; 256];
/// let n = monitor_core::json::encode(&monitor_core::RouteSummary::default(), &mut buf).unwrap();
/// assert!(buf[..n].starts_with(b"{\"frames\":0,"));
/// ```
pub fn encode<T: Serialize + ?Sized>(value: &T, buf: &mut [u8]) -> Result<usize, JsonError> {
    serde_json_core::to_slice(value, buf).map_err(|_| JsonError::BufferFull)
}
