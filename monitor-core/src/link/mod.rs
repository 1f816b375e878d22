//! The monitor on a live link (docs/SCORE.md, "Live link"): a *checker* on a separate safety
//! controller receives the *doer*'s frames over a byte stream (a UART, a TCP socket, a pipe),
//! checks every message end to end, feeds the frames it accepts to a [`crate::Monitor`], and
//! answers with events, status and summary messages. A link fault never becomes a wrong verdict:
//! a message that fails its check is dropped, and the checker says when it can no longer see.
//!
//! One concept per file:
//!
//! | file | what |
//! |---|---|
//! | [`e2e`] | the 12-byte header and its check, as AUTOSAR E2E Profile 4 protects a message |
//! | [`framing`] | COBS with a 0x00 delimiter on a byte stream, and the receiving side's buffer |
//! | [`payload`] | the data ids and the fixed little-endian payload layouts |
//! | [`checker`] | the check status of each message, the VALID/INVALID window, segments |
//!
//! ```
//! use monitor_core::link::{self, Checker, LinkConfig, Message};
//! use monitor_core::{Config, Frame};
//!
//! // The doer's side: a start, 40 frames, an end, each one framed on the byte stream.
//! let mut wire = Vec::new();
//! let mut buf = [0u8; link::MAX_ENCODED];
//! let n = link::encode(&Message::Start(Config::DEFAULT), 0, &mut buf);
//! wire.extend_from_slice(&buf[..n]);
//! let cruise = Frame { speed: 8.0, lat_err: Some(0.1), ..Frame::default() };
//! for counter in 0..40u16 {
//!     let n = link::encode(&Message::Frame(cruise), counter, &mut buf);
//!     wire.extend_from_slice(&buf[..n]);
//! }
//! let n = link::encode(&Message::End { frames: 40 }, 0, &mut buf);
//! wire.extend_from_slice(&buf[..n]);
//!
//! // The checker's side: bytes in, messages out.
//! let mut checker: Checker = Checker::new(LinkConfig::DEFAULT).unwrap();
//! let mut answers = Vec::new();
//! checker.receive(&wire, 0, &mut |bytes: &[u8]| answers.extend_from_slice(bytes));
//! let mut rx = link::Deframer::new();
//! let mut summary = None;
//! for &b in &answers {
//!     if let Some(Ok(msg)) = rx.push(b) {
//!         if let Ok((_, Message::Summary(s))) = link::decode(msg) {
//!             summary = Some(s);
//!         }
//!     }
//! }
//! let s = summary.unwrap();
//! assert_eq!((s.route.frames, s.route.comfort.chunks, s.segments), (40, 2, 1));
//! assert_eq!(s.counts.get(link::CheckStatus::Ok), 40);
//! ```

pub mod checker;
pub mod e2e;
pub mod framing;
pub mod payload;

pub use checker::{CheckStatus, Checker, LinkConfig, LinkConfigError, StatusCounts};
pub use e2e::{Header, HEADER_LEN};
pub use framing::{Deframer, FramingError, MAX_ENCODED};
pub use payload::{
    decode, encode, seal, DecodeError, LinkEvent, LinkState, LinkSummary, Message, RouteState,
    Status, Tagged, DATA_END, DATA_EVENT, DATA_FRAME, DATA_START, DATA_STATUS, DATA_SUMMARY,
    MAX_MESSAGE,
};
