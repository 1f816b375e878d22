//! Streams the messages of an MCAP file in file order, in bounded memory, whatever the file holds.
//!
//! - The file is opened as every input is ([`open_input`]): a regular file, without blocking,
//!   its magic checked before anything else is read; its bytes are never printed.
//! - Records are read one at a time ([`LinearReader`], chunks whole and still compressed, at most
//!   [`RECORD_LIMIT`] bytes). A chunk is decompressed as a stream: a message of a topic nobody
//!   reads is skipped as it is decoded, never held; and a chunk whose message index (the records
//!   that follow it) names only channels nobody reads is not decompressed at all.
//! - A chunk's `uncompressed_crc` and the data section's `data_section_crc` are checked when they
//!   are not 0. A chunk that is corrupt (its CRC differs, a record runs past its end, a record
//!   that MCAP does not define, a message on an undefined channel) is named with its reason and
//!   skipped whole; reading goes on with the next chunk ([`Streamed::corrupt_chunks`]).
//! - A file cut short (a recorder killed, a copy interrupted) gives every message before the
//!   cut, and how much was lost ([`Streamed::truncated`]).
//! - A chunk's bytes count against the run's bytes in flight ([`Hold`]), as telemetry's do.
//!
//! ```
//! use monitor_host::input::mcap::stream::{stream_from, StreamError};
//! // The MCAP magic followed by zeros is refused at the first record, not read to the end.
//! let mut bytes = b"\x89MCAP0\r\n".to_vec();
//! bytes.extend(std::iter::repeat(0u8).take(1 << 20));
//! let e = stream_from(&bytes[..], bytes.len() as u64, &|_| true, |_| Ok(())).unwrap_err();
//! assert!(matches!(e, StreamError::Corrupt { .. }), "{e}");
//! assert!(e.to_string().contains("opcode 0x00"), "{e}");
//! ```

use std::collections::BTreeMap;
use std::io::{self, Read};
use std::path::Path;
use std::sync::Arc;

use ::mcap::records::{op, ChunkHeader};
use ::mcap::sans_io::linear_reader::{LinearReadEvent, LinearReader, LinearReaderOptions};

use crate::input::read::{open_input, read_up_to, FileKind, Hold};

/// The MCAP magic that opens (and closes) every file.
pub const MAGIC: &[u8; 8] = b"\x89MCAP0\r\n";

/// The largest record read whole: a record outside chunks, a chunk (compressed), or a message
/// of a topic that is read. A longer one is refused (a corrupt length must not allocate
/// gigabytes); a message of a topic nobody reads is skipped whatever its length.
pub const RECORD_LIMIT: usize = 256 << 20;

/// The largest schema or channel record inside a chunk.
const SMALL_RECORD_LIMIT: u64 = 16 << 20;

/// A read asking for more than this takes bytes of the run's budget ([`Hold`]).
const HOLD_ABOVE: usize = 8 << 20;

/// The bytes of a message record before its data: channel id, sequence, log and publish time.
const MESSAGE_HEADER: usize = 2 + 4 + 8 + 8;

/// A schema, as its record gives it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Schema {
    /// The type's name (`nav_msgs/msg/Odometry`).
    pub name: String,
    /// The schema encoding (`ros2msg`, `ros2idl`, ...).
    pub encoding: String,
    /// The definition.
    pub data: Vec<u8>,
}

/// A channel, as its record gives it, with its schema.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Channel {
    /// The channel id (per file).
    pub id: u16,
    /// The topic.
    pub topic: String,
    /// The message encoding (`cdr`).
    pub message_encoding: String,
    /// The schema, when the channel has one (schema id not 0 and defined).
    pub schema: Option<Arc<Schema>>,
}

/// One message of a topic that is read.
#[derive(Debug)]
pub struct Message<'a> {
    /// Its channel.
    pub channel: &'a Channel,
    /// Log time, ns.
    pub log_time: u64,
    /// The message's bytes.
    pub data: &'a [u8],
}

/// Where a file's data section ended early.
#[derive(Debug, Clone, PartialEq)]
pub struct Truncation {
    /// What happened (`the file ends in the middle of a record`).
    pub reason: String,
    /// Bytes after the last complete message (or chunk), lost.
    pub lost_bytes: u64,
    /// The messages lost, estimated from `lost_bytes` and the mean size of the messages read
    /// (the index that would count them sits in the lost summary).
    pub lost_messages_estimate: u64,
}

/// A chunk skipped because it is corrupt.
#[derive(Debug, Clone, PartialEq)]
pub struct CorruptChunk {
    /// Its place among the file's chunks (0-based).
    pub index: u64,
    /// Byte offset of the chunk record in the file.
    pub offset: u64,
    /// Log times its header gives (ns): the first and the last message.
    pub times: (u64, u64),
    /// What is wrong.
    pub reason: String,
    /// Messages it held, from its message index, when the file has one.
    pub messages: Option<u64>,
}

/// How many messages a topic has, and its type.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct TopicCount {
    /// The schema name of its first channel (empty without a schema).
    pub type_name: String,
    /// The message encoding.
    pub encoding: String,
    /// Messages seen (read or skipped).
    pub messages: u64,
}

/// What streaming one file gave.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Streamed {
    /// Messages seen, on every topic.
    pub messages: u64,
    /// Bytes of the file.
    pub bytes: u64,
    /// Every topic seen, with its type and message count.
    pub topics: BTreeMap<String, TopicCount>,
    /// Set when the file ends before its data section does.
    pub truncated: Option<Truncation>,
    /// Chunks skipped because they are corrupt.
    pub corrupt_chunks: Vec<CorruptChunk>,
    /// Chunks not decompressed: their message index names only topics nobody reads.
    pub skipped_chunks: u64,
}

/// Why a file cannot be streamed at all.
#[derive(Debug, thiserror::Error)]
pub enum StreamError {
    /// The file cannot be opened or read.
    #[error("cannot read: {0}")]
    Io(#[from] io::Error),
    /// Not an MCAP file (its bytes are not printed), or not a file sds reads.
    #[error("{0}")]
    NotMcap(String),
    /// The file is corrupt outside a chunk (or its data section's CRC differs).
    #[error("corrupt MCAP after {messages} messages: {reason}")]
    Corrupt {
        /// Messages seen before.
        messages: u64,
        /// What is wrong, and where.
        reason: String,
    },
    /// The callback refused a message.
    #[error("{0}")]
    Refused(String),
}

/// Streams the messages of the MCAP file at `path` whose topic is `wanted`, in file order, to
/// `each`; counts every topic's messages.
///
/// # Errors
/// [`StreamError`]: unreadable, not a regular file, not MCAP, corrupt outside a chunk, or
/// refused by `each`. A file cut short or a corrupt chunk is not an error: [`Streamed`] says so.
pub fn stream(
    path: &Path,
    wanted: &dyn Fn(&str) -> bool,
    each: impl FnMut(&Message<'_>) -> Result<(), String>,
) -> Result<Streamed, StreamError> {
    let opened = open_input(path, FileKind::McapLog).map_err(|e| match e.kind() {
        io::ErrorKind::InvalidData | io::ErrorKind::InvalidInput => {
            StreamError::NotMcap(e.to_string())
        }
        _ => StreamError::Io(e),
    })?;
    let bytes = opened.size;
    stream_from(opened.take(), bytes, wanted, each)
}

/// [`stream`] from bytes already opened (`bytes`: the file's size, for the truncation's
/// estimate), starting at the magic.
///
/// # Errors
/// As [`stream`].
pub fn stream_from(
    mut source: impl Read,
    bytes: u64,
    wanted: &dyn Fn(&str) -> bool,
    each: impl FnMut(&Message<'_>) -> Result<(), String>,
) -> Result<Streamed, StreamError> {
    let options = LinearReaderOptions::default()
        .with_skip_end_magic(true)
        .with_emit_chunks(true)
        .with_validate_data_section_crc(true)
        .with_record_length_limit(RECORD_LIMIT);
    let mut reader = LinearReader::new_with_options(options);
    let mut state = State {
        wanted,
        each,
        channels: BTreeMap::new(),
        schemas: BTreeMap::new(),
        pending: None,
        chunks: 0,
        out: Streamed {
            bytes,
            ..Streamed::default()
        },
        fed: 0,
        at_last: 0,
    };
    let mut hold: Option<Hold> = None;
    while let Some(event) = reader.next_event() {
        match event {
            Ok(LinearReadEvent::ReadRequest(need)) => {
                if need > HOLD_ABOVE && hold.is_none() {
                    // One hold at a time per log: a worker never waits while it holds bytes.
                    state.flush(false)?;
                    // The record's bytes, and the copy of a chunk kept until its index is read.
                    hold = Some(Hold::take(2 * need as u64));
                }
                let n = loop {
                    match source.read(reader.insert(need)) {
                        Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
                        r => break r?,
                    }
                };
                state.fed += n as u64;
                reader.notify_read(n);
            }
            Ok(LinearReadEvent::Record { opcode, data }) => {
                let done = state.record(opcode, data, hold.take())?;
                if done {
                    break;
                }
            }
            Err(::mcap::McapError::UnexpectedEof) | Err(::mcap::McapError::UnexpectedEoc) => {
                state.flush(false)?;
                let out = &mut state.out;
                let lost_bytes = bytes.saturating_sub(state.at_last);
                let mean = (state.at_last / out.messages.max(1)).max(1);
                out.truncated = Some(Truncation {
                    reason: "the file ends in the middle of a record".into(),
                    lost_bytes,
                    lost_messages_estimate: lost_bytes.div_ceil(mean),
                });
                return Ok(state.out);
            }
            Err(::mcap::McapError::BadMagic) => {
                return Err(StreamError::NotMcap(
                    "not an MCAP file: it does not start with the MCAP magic".into(),
                ))
            }
            Err(::mcap::McapError::BadDataCrc { saved, calculated }) => {
                state.flush(true)?;
                // A corrupt chunk already named explains it; otherwise the corruption is
                // somewhere no chunk CRC covers.
                if state.out.corrupt_chunks.is_empty() {
                    return Err(StreamError::Corrupt {
                        messages: state.out.messages,
                        reason: format!(
                            "the data section's CRC is {calculated:08x}, its Data End record \
                             says {saved:08x}: bytes of the file changed; sds does not score a \
                             log it cannot trust"
                        ),
                    });
                }
                return Ok(state.out);
            }
            Err(e) => {
                return Err(StreamError::Corrupt {
                    messages: state.out.messages,
                    reason: format!("after byte {}: {e}", state.fed),
                })
            }
        }
    }
    state.flush(true)?;
    Ok(state.out)
}

/// A chunk read, kept (compressed) until the message index records after it are read.
struct Pending {
    header: ChunkHeader,
    data: Vec<u8>,
    index: u64,
    offset: u64,
    /// Channel id → messages, from the message index records after the chunk.
    indexed: BTreeMap<u16, u64>,
    _hold: Option<Hold>,
}

struct State<'w, F> {
    wanted: &'w dyn Fn(&str) -> bool,
    each: F,
    channels: BTreeMap<u16, Channel>,
    schemas: BTreeMap<u16, Arc<Schema>>,
    pending: Option<Pending>,
    chunks: u64,
    out: Streamed,
    /// Bytes given to the reader: at a record, the end of that record.
    fed: u64,
    /// `fed` at the last message delivered.
    at_last: u64,
}

/// A message read out of a chunk, delivered once the chunk's CRC holds.
struct Kept {
    channel: u16,
    log_time: u64,
    data: Vec<u8>,
}

impl<F: FnMut(&Message<'_>) -> Result<(), String>> State<'_, F> {
    /// Handles one record outside chunks; `true` at the end of the data section.
    fn record(&mut self, opcode: u8, data: &[u8], hold: Option<Hold>) -> Result<bool, StreamError> {
        if opcode == op::MESSAGE_INDEX {
            if let (Some(p), Ok(::mcap::records::Record::MessageIndex(m))) =
                (self.pending.as_mut(), parse_record(opcode, data))
            {
                *p.indexed.entry(m.channel_id).or_default() += m.records.len() as u64;
            }
            return Ok(false);
        }
        self.flush(true)?;
        let start = self.fed - 9 - data.len() as u64;
        match opcode {
            0 => {
                return Err(StreamError::Corrupt {
                    messages: self.out.messages,
                    reason: format!(
                        "byte {start}: a record with opcode 0x00, which MCAP does not define (the \
                         file holds zeros from here?)"
                    ),
                })
            }
            op::DATA_END => return Ok(true),
            op::CHUNK => {
                let (header, body) = match parse_record(opcode, data) {
                    Ok(::mcap::records::Record::Chunk { header, data }) => (header, data),
                    Ok(_) => unreachable!("a chunk's opcode parses as a chunk"),
                    Err(e) => {
                        // The record's length held: the next record is read as usual.
                        self.out.corrupt_chunks.push(CorruptChunk {
                            index: self.chunks,
                            offset: start,
                            times: (0, 0),
                            reason: format!("its header cannot be read: {e}"),
                            messages: None,
                        });
                        self.chunks += 1;
                        return Ok(false);
                    }
                };
                self.pending = Some(Pending {
                    data: body.into_owned(),
                    header,
                    index: self.chunks,
                    offset: start,
                    indexed: BTreeMap::new(),
                    _hold: hold,
                });
                self.chunks += 1;
            }
            op::SCHEMA | op::CHANNEL => {
                if let Err(reason) = self.define(opcode, data) {
                    return Err(StreamError::Corrupt {
                        messages: self.out.messages,
                        reason: format!("byte {start}: {reason}"),
                    });
                }
            }
            op::MESSAGE => {
                let Some((id, log_time)) = message_header(data) else {
                    return Err(StreamError::Corrupt {
                        messages: self.out.messages,
                        reason: format!("byte {start}: a message record of {} bytes", data.len()),
                    });
                };
                let Some(channel) = self.channels.get(&id) else {
                    return Err(StreamError::Corrupt {
                        messages: self.out.messages,
                        reason: format!(
                            "byte {start}: a message on channel {id}, which no channel record \
                             defines"
                        ),
                    });
                };
                count(&mut self.out, channel, 1);
                if (self.wanted)(&channel.topic) {
                    self.at_last = self.fed;
                    (self.each)(&Message {
                        channel,
                        log_time,
                        data: &data[MESSAGE_HEADER..],
                    })
                    .map_err(StreamError::Refused)?;
                }
            }
            _ => {}
        }
        Ok(false)
    }

    /// Registers a schema or channel record.
    fn define(&mut self, opcode: u8, data: &[u8]) -> Result<(), String> {
        match parse_record(opcode, data)? {
            ::mcap::records::Record::Schema { header, data } => {
                self.schemas.insert(
                    header.id,
                    Arc::new(Schema {
                        name: header.name,
                        encoding: header.encoding,
                        data: data.into_owned(),
                    }),
                );
            }
            ::mcap::records::Record::Channel(c) => {
                let schema = self.schemas.get(&c.schema_id).cloned();
                self.channels.insert(
                    c.id,
                    Channel {
                        id: c.id,
                        topic: c.topic,
                        message_encoding: c.message_encoding,
                        schema,
                    },
                );
            }
            _ => {}
        }
        Ok(())
    }

    /// Reads the pending chunk, if any. `indexed`: the message index after it is complete (the
    /// next record was read), so a chunk of unread channels only is skipped undecoded.
    fn flush(&mut self, indexed: bool) -> Result<(), StreamError> {
        let Some(p) = self.pending.take() else {
            return Ok(());
        };
        let unread = |id: &u16| {
            self.channels
                .get(id)
                .is_some_and(|c| !(self.wanted)(&c.topic))
        };
        if indexed && !p.indexed.is_empty() && p.indexed.keys().all(unread) {
            for (id, n) in &p.indexed {
                if let Some(c) = self.channels.get(id) {
                    count(&mut self.out, c, *n);
                }
            }
            self.out.skipped_chunks += 1;
            return Ok(());
        }
        let mut defined = Vec::new();
        match self.decode(&p, &mut defined) {
            Ok((kept, counts)) => {
                for (opcode, data) in defined {
                    // Checked when decoded.
                    self.define(opcode, &data).ok();
                }
                for (id, n) in counts {
                    if let Some(c) = self.channels.get(&id) {
                        count(&mut self.out, c, n);
                    }
                }
                self.at_last = self.fed;
                for k in kept {
                    let channel = &self.channels[&k.channel];
                    (self.each)(&Message {
                        channel,
                        log_time: k.log_time,
                        data: &k.data,
                    })
                    .map_err(StreamError::Refused)?;
                }
            }
            Err(reason) => {
                let messages = (!p.indexed.is_empty()).then(|| p.indexed.values().sum());
                self.out.corrupt_chunks.push(CorruptChunk {
                    index: p.index,
                    offset: p.offset,
                    times: (p.header.message_start_time, p.header.message_end_time),
                    reason,
                    messages,
                });
            }
        }
        Ok(())
    }

    /// Decodes a chunk: the messages of read topics, and every channel's message count; the
    /// schema and channel records it defines go to `defined` (registered once the chunk holds).
    fn decode(
        &self,
        p: &Pending,
        defined: &mut Vec<(u8, Vec<u8>)>,
    ) -> Result<(Vec<Kept>, BTreeMap<u16, u64>), String> {
        let size = p.header.uncompressed_size;
        let inner: Box<dyn Read + '_> = match p.header.compression.as_str() {
            "" => Box::new(&p.data[..]),
            "zstd" => Box::new(
                zstd::stream::read::Decoder::with_buffer(&p.data[..])
                    .map_err(|e| format!("zstd: {e}"))?,
            ),
            "lz4" => Box::new(lz4::Decoder::new(&p.data[..]).map_err(|e| format!("lz4: {e}"))?),
            other => {
                return Err(format!(
                    "compressed with {other:?}, which sds does not read (zstd, lz4 or none)"
                ))
            }
        };
        let mut r = Hashing {
            inner: inner.take(size),
            hasher: crc32fast::Hasher::new(),
            read: 0,
        };
        let mut kept = Vec::new();
        let mut counts: BTreeMap<u16, u64> = BTreeMap::new();
        // Channels defined inside this chunk, usable by its later messages.
        let mut local: BTreeMap<u16, Channel> = BTreeMap::new();
        let mut local_schemas: BTreeMap<u16, Arc<Schema>> = BTreeMap::new();
        let io = |e: io::Error| format!("cannot decompress: {e}");
        loop {
            let at = r.read;
            let mut head = [0u8; 9];
            let got = read_up_to(&mut r, &mut head).map_err(io)?;
            if got == 0 {
                break;
            }
            if got < head.len() {
                return Err(format!(
                    "it ends in the middle of a record at byte {at} of its {size}"
                ));
            }
            let opcode = head[0];
            let len = u64::from_le_bytes(head[1..].try_into().unwrap_or_default());
            if opcode == 0 {
                return Err(format!(
                    "byte {at} of its records holds opcode 0x00, which MCAP does not define \
                     (zeros?)"
                ));
            }
            if len > size - at - 9 {
                return Err(format!(
                    "a record of {len} bytes at byte {at} runs past its end ({size} bytes): \
                     the chunk ends in the middle of a record"
                ));
            }
            match opcode {
                op::SCHEMA | op::CHANNEL => {
                    if len > SMALL_RECORD_LIMIT {
                        return Err(format!("a schema or channel record of {len} bytes"));
                    }
                    let mut data = vec![0u8; len as usize];
                    r.read_exact(&mut data).map_err(io)?;
                    match parse_record(opcode, &data)? {
                        ::mcap::records::Record::Schema { header, data: d } => {
                            local_schemas.insert(
                                header.id,
                                Arc::new(Schema {
                                    name: header.name,
                                    encoding: header.encoding,
                                    data: d.into_owned(),
                                }),
                            );
                        }
                        ::mcap::records::Record::Channel(c) => {
                            let schema = local_schemas
                                .get(&c.schema_id)
                                .or_else(|| self.schemas.get(&c.schema_id))
                                .cloned();
                            local.insert(
                                c.id,
                                Channel {
                                    id: c.id,
                                    topic: c.topic,
                                    message_encoding: c.message_encoding,
                                    schema,
                                },
                            );
                        }
                        _ => {}
                    }
                    defined.push((opcode, data));
                }
                op::MESSAGE => {
                    if len < MESSAGE_HEADER as u64 {
                        return Err(format!("a message record of {len} bytes at byte {at}"));
                    }
                    let mut mh = [0u8; MESSAGE_HEADER];
                    r.read_exact(&mut mh).map_err(io)?;
                    let (id, log_time) = message_header(&mh).unwrap_or_default();
                    let channel = local.get(&id).or_else(|| self.channels.get(&id));
                    let Some(channel) = channel else {
                        return Err(format!(
                            "a message on channel {id}, which no channel record defines"
                        ));
                    };
                    *counts.entry(id).or_default() += 1;
                    let body = len - MESSAGE_HEADER as u64;
                    if (self.wanted)(&channel.topic) {
                        if body > RECORD_LIMIT as u64 {
                            return Err(format!(
                                "a message of {body} bytes on {}, over the {} MiB limit of a \
                                 message that is read",
                                channel.topic,
                                RECORD_LIMIT >> 20
                            ));
                        }
                        let mut data = vec![0u8; body as usize];
                        r.read_exact(&mut data).map_err(io)?;
                        kept.push(Kept {
                            channel: id,
                            log_time,
                            data,
                        });
                    } else {
                        skip(&mut r, body).map_err(io)?;
                    }
                }
                _ => skip(&mut r, len).map_err(io)?,
            }
        }
        if r.read != size {
            return Err(format!(
                "its records decompress to {} bytes, its header says {size}",
                r.read
            ));
        }
        let crc = r.hasher.finalize();
        if p.header.uncompressed_crc != 0 && crc != p.header.uncompressed_crc {
            return Err(format!(
                "its CRC is {crc:08x}, its header says {:08x}: bytes of the chunk changed",
                p.header.uncompressed_crc
            ));
        }
        Ok((kept, counts))
    }
}

/// Counts `n` messages of `channel`'s topic.
fn count(out: &mut Streamed, channel: &Channel, n: u64) {
    out.messages += n;
    let entry = out.topics.entry(channel.topic.clone()).or_default();
    if entry.messages == 0 && entry.type_name.is_empty() {
        entry.type_name = channel
            .schema
            .as_ref()
            .map(|s| s.name.clone())
            .unwrap_or_default();
        entry.encoding = channel.message_encoding.clone();
    }
    entry.messages += n;
}

/// A message record's channel id and log time.
fn message_header(data: &[u8]) -> Option<(u16, u64)> {
    let id = u16::from_le_bytes(data.get(0..2)?.try_into().ok()?);
    let log_time = u64::from_le_bytes(data.get(6..14)?.try_into().ok()?);
    (data.len() >= MESSAGE_HEADER).then_some((id, log_time))
}

/// Reads and drops `n` bytes.
fn skip(r: &mut impl Read, n: u64) -> io::Result<()> {
    let copied = io::copy(&mut r.take(n), &mut io::sink())?;
    if copied < n {
        return Err(io::Error::new(
            io::ErrorKind::UnexpectedEof,
            "the chunk's records end early",
        ));
    }
    Ok(())
}

/// A reader that hashes (CRC-32) and counts what it reads.
struct Hashing<R> {
    inner: R,
    hasher: crc32fast::Hasher,
    read: u64,
}

impl<R: Read> Read for Hashing<R> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let n = self.inner.read(buf)?;
        self.hasher.update(&buf[..n]);
        self.read += n as u64;
        Ok(n)
    }
}

/// [`::mcap::parse_record`], after checking that every length inside the record (a string's, a
/// byte array's, a map's) fits in what is left of it: the mcap crate reserves a field's length
/// before it reads it, so a length of 4 GiB in a 40-byte record asked for 4 GiB (found by the
/// `mcap` fuzz target).
fn parse_record(opcode: u8, data: &[u8]) -> Result<::mcap::records::Record<'_>, String> {
    if !lengths_fit(opcode, data) {
        return Err("a length inside the record runs past its end".into());
    }
    ::mcap::parse_record(opcode, data).map_err(|e| e.to_string())
}

/// Whether the length-prefixed fields of a record of the opcodes read here fit in it.
fn lengths_fit(opcode: u8, data: &[u8]) -> bool {
    let mut at = Fields { data, at: 0 };
    match opcode {
        // id, name, encoding, data
        op::SCHEMA => at.skip(2) && at.string() && at.string() && at.bytes32(),
        // id, schema id, topic, message encoding, metadata (a map of strings)
        op::CHANNEL => at.skip(4) && at.string() && at.string() && at.map(),
        // start, end, uncompressed size, uncompressed crc, compression, records
        op::CHUNK => at.skip(28) && at.string() && at.bytes64(),
        // channel id, entries
        op::MESSAGE_INDEX => at.skip(2) && at.bytes32(),
        _ => true,
    }
}

/// A cursor over a record's fields.
struct Fields<'a> {
    data: &'a [u8],
    at: usize,
}

impl Fields<'_> {
    fn skip(&mut self, n: usize) -> bool {
        match self.at.checked_add(n) {
            Some(end) if end <= self.data.len() => {
                self.at = end;
                true
            }
            _ => false,
        }
    }
    fn len32(&mut self) -> Option<usize> {
        let b = self.data.get(self.at..self.at.checked_add(4)?)?;
        self.at += 4;
        Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize)
    }
    fn string(&mut self) -> bool {
        self.len32().is_some_and(|n| self.skip(n))
    }
    fn bytes32(&mut self) -> bool {
        self.string()
    }
    fn bytes64(&mut self) -> bool {
        let Some(b) = self
            .at
            .checked_add(8)
            .and_then(|e| self.data.get(self.at..e))
        else {
            return false;
        };
        let mut n = [0u8; 8];
        n.copy_from_slice(b);
        self.at += 8;
        usize::try_from(u64::from_le_bytes(n)).is_ok_and(|n| self.skip(n))
    }
    /// A map of strings: its byte length, then key and value strings that fill it exactly.
    fn map(&mut self) -> bool {
        let Some(n) = self.len32() else {
            return false;
        };
        let Some(end) = self.at.checked_add(n).filter(|&e| e <= self.data.len()) else {
            return false;
        };
        let mut inner = Fields {
            data: &self.data[..end],
            at: self.at,
        };
        while inner.at < end {
            if !(inner.string() && inner.string()) {
                return false;
            }
        }
        self.at = end;
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 40-byte chunk record whose compression string claims 4 GiB is refused before the mcap
    /// crate reserves the 4 GiB (the `mcap` fuzz target's out-of-memory input).
    #[test]
    fn a_length_past_the_record_is_refused_before_it_is_reserved() {
        let mut chunk = vec![0u8; 28];
        chunk.extend_from_slice(&u32::MAX.to_le_bytes());
        chunk.extend_from_slice(&[0u8; 8]);
        assert!(!lengths_fit(op::CHUNK, &chunk));
        assert!(parse_record(op::CHUNK, &chunk).is_err());
        // The same record with an empty compression and no records fits and parses.
        let mut ok = vec![0u8; 28];
        ok.extend_from_slice(&0u32.to_le_bytes());
        ok.extend_from_slice(&0u64.to_le_bytes());
        assert!(lengths_fit(op::CHUNK, &ok));
        assert!(parse_record(op::CHUNK, &ok).is_ok());
        // A channel whose metadata map holds a string running past the map.
        let mut channel = vec![0u8; 4];
        channel.extend_from_slice(&1u32.to_le_bytes());
        channel.push(b'/');
        channel.extend_from_slice(&3u32.to_le_bytes());
        channel.extend_from_slice(b"cdr");
        channel.extend_from_slice(&8u32.to_le_bytes());
        channel.extend_from_slice(&100u32.to_le_bytes());
        channel.extend_from_slice(&[0u8; 4]);
        assert!(!lengths_fit(op::CHANNEL, &channel));
    }
}
