//! Streams the messages of an MCAP file in file order with the `mcap` crate's sans-io reader:
//! memory holds one record or chunk at a time, whatever the file's size. A file cut short (a
//! recorder killed, a copy interrupted) gives every message before the cut, and how much was
//! lost.

use std::fs::File;
use std::io::{BufReader, Read};
use std::path::Path;

use ::mcap::sans_io::{LinearReaderOptions, MessageReadEvent, MessageReader};
use ::mcap::Message;

/// The MCAP magic that opens (and closes) every file.
pub const MAGIC: &[u8; 8] = b"\x89MCAP0\r\n";

/// A record longer than this is refused (a corrupt length must not allocate gigabytes).
const RECORD_LIMIT: usize = 1 << 30;

/// Where a file's data section ended early.
#[derive(Debug, Clone, PartialEq)]
pub struct Truncation {
    /// The reader's message (`MCAP file ended in the middle of a record`, ...).
    pub reason: String,
    /// Bytes after the last complete message (or chunk), lost.
    pub lost_bytes: u64,
    /// The messages lost, estimated from `lost_bytes` and the mean size of the messages read
    /// (the index that would count them sits in the lost summary).
    pub lost_messages_estimate: u64,
}

/// What streaming one file gave.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Streamed {
    /// Messages read.
    pub messages: u64,
    /// Bytes of the file.
    pub bytes: u64,
    /// Set when the file ends before its data section does.
    pub truncated: Option<Truncation>,
}

/// Why a file cannot be streamed at all.
#[derive(Debug, thiserror::Error)]
pub enum StreamError {
    /// The file cannot be opened or read.
    #[error("cannot read: {0}")]
    Io(#[from] std::io::Error),
    /// The file does not start with the MCAP magic.
    #[error(
        "not an MCAP file: it starts with {0:02x?}, not the MCAP magic 89 4d 43 41 50 30 0d 0a{1}"
    )]
    NotMcap(Vec<u8>, &'static str),
    /// A record that is not MCAP (a corrupt file rather than a cut one).
    #[error("corrupt MCAP after {messages} messages: {reason}")]
    Corrupt {
        /// Messages read before.
        messages: u64,
        /// The reader's message.
        reason: String,
    },
    /// The callback refused a message.
    #[error("{0}")]
    Refused(String),
}

/// Counts the bytes handed to the reader: the position in the file.
struct Counting<R> {
    inner: R,
    read: u64,
}

impl<R: Read> Read for Counting<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.inner.read(buf)?;
        self.read += n as u64;
        Ok(n)
    }
}

/// Streams the messages of the MCAP file at `path` in file order to `each`.
///
/// # Errors
/// [`StreamError`]: unreadable, not MCAP, corrupt, or refused by `each`. A file cut short is
/// not an error: [`Streamed::truncated`] says so.
pub fn stream(
    path: &Path,
    mut each: impl FnMut(&Message<'static>) -> Result<(), String>,
) -> Result<Streamed, StreamError> {
    let file = File::open(path)?;
    let bytes = file.metadata()?.len();
    let mut source = Counting {
        inner: BufReader::with_capacity(1 << 16, file),
        read: 0,
    };
    let mut magic = [0u8; 8];
    let got = read_up_to(&mut source, &mut magic)?;
    if &magic[..got] != MAGIC.as_slice() {
        let hint = if magic[..got].starts_with(b"SQLite f") {
            ": a rosbag2 sqlite3 log; convert it with `ros2 bag convert` to MCAP"
        } else {
            ""
        };
        return Err(StreamError::NotMcap(magic[..got].to_vec(), hint));
    }
    // The data section ends at its Data End record: the summary after it repeats what was read.
    let options = LinearReaderOptions::default()
        .with_skip_start_magic(true)
        .with_skip_end_magic(true)
        .with_record_length_limit(RECORD_LIMIT);
    let mut reader = MessageReader::new_with_options(options);
    let mut out = Streamed {
        bytes,
        ..Streamed::default()
    };
    let mut at_last = source.read;
    while let Some(event) = reader.next_event() {
        match event {
            Ok(MessageReadEvent::ReadRequest(need)) => {
                let n = loop {
                    match source.read(reader.insert(need)) {
                        Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
                        r => break r?,
                    }
                };
                reader.notify_read(n);
            }
            Ok(MessageReadEvent::Message(m)) => {
                out.messages += 1;
                at_last = source.read;
                each(&m).map_err(StreamError::Refused)?;
            }
            Err(::mcap::McapError::UnexpectedEof) | Err(::mcap::McapError::UnexpectedEoc) => {
                let lost_bytes = bytes.saturating_sub(at_last);
                let mean = (at_last / out.messages.max(1)).max(1);
                out.truncated = Some(Truncation {
                    reason: "the file ends in the middle of a record".into(),
                    lost_bytes,
                    lost_messages_estimate: lost_bytes.div_ceil(mean),
                });
                return Ok(out);
            }
            Err(e) => {
                return Err(StreamError::Corrupt {
                    messages: out.messages,
                    reason: e.to_string(),
                })
            }
        }
    }
    Ok(out)
}

fn read_up_to(r: &mut impl Read, buf: &mut [u8]) -> std::io::Result<usize> {
    let mut got = 0;
    while got < buf.len() {
        match r.read(&mut buf[got..]) {
            Ok(0) => break,
            Ok(n) => got += n,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
    Ok(got)
}
