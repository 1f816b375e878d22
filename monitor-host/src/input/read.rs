//! The one way an input file is read: regular files only, never more than a size bound per file
//! kind, its magic checked first where the kind has one. Every reader of `input/` (and the
//! merge's parts) goes through [`read_input`], or [`open_input`] for a file that is streamed
//! (an MCAP log); none opens files itself.
//!
//! Why: a FIFO named `metric_info.json` would block the tool forever, and a link to `/dev/zero`
//! would be read until memory runs out. The file is opened without blocking (`O_NONBLOCK`), its
//! type checked on the open handle (no race between a check and the open), and at most
//! [`FileKind::max_bytes`] + 1 bytes are read. A leading UTF-8 byte order mark is skipped.
//!
//! ```
//! use monitor_host::input::read::{read_input, FileKind};
//! let dir = tempfile::tempdir()?;
//! let p = dir.path().join("labels.json");
//! std::fs::write(&p, "{}")?;
//! assert_eq!(read_input(&p, FileKind::Labels)?, b"{}");
//! let e = read_input(dir.path(), FileKind::Labels).unwrap_err();
//! assert_eq!(e.to_string(), "a directory, not a regular file (sds reads only regular files)");
//! # Ok::<(), std::io::Error>(())
//! ```

use std::fs::{File, OpenOptions};
use std::io::{self, Read};
use std::path::Path;

/// What an input file is; each kind has its own size bound.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum FileKind {
    /// An evaluator results file (raw or merged).
    Results,
    /// A route's `metric_info.json`.
    MetricInfo,
    /// LEAD's `infractions.json`.
    LeadInfractions,
    /// A route XML file.
    RouteXml,
    /// A label file (`--families`, `--weathers`).
    Labels,
    /// An OpenDRIVE map.
    Map,
    /// A JSON report read back as a part of `sds merge`.
    Report,
    /// An MCAP vehicle log: streamed, never read whole ([`open_input`]).
    McapLog,
}

const MIB: u64 = 1 << 20;

impl FileKind {
    /// The largest file of this kind that is read, in bytes. Far above any real file: a merged
    /// results file of 220 routes is ~1 MB, a 100,000-frame `metric_info.json` ~100 MB, the
    /// 220-route XML ~1 MB, CARLA's largest map (Town12) ~100 MB.
    pub const fn max_bytes(self) -> u64 {
        match self {
            FileKind::Results => 256 * MIB,
            FileKind::MetricInfo => 1024 * MIB,
            FileKind::LeadInfractions => 64 * MIB,
            FileKind::RouteXml => 256 * MIB,
            FileKind::Labels => 16 * MIB,
            FileKind::Map => 1024 * MIB,
            FileKind::Report => 256 * MIB,
            // Streamed in bounded memory: the bound stops a runaway file, not a long drive
            // (a day of camera-less driving logs at 100 Hz is a few GB).
            FileKind::McapLog => 1 << 40,
        }
    }

    /// How the kind is named in messages.
    pub const fn name(self) -> &'static str {
        match self {
            FileKind::Results => "results file",
            FileKind::MetricInfo => "metric_info.json",
            FileKind::LeadInfractions => "infractions.json",
            FileKind::RouteXml => "route XML file",
            FileKind::Labels => "label file",
            FileKind::Map => "map",
            FileKind::Report => "report",
            FileKind::McapLog => "MCAP file",
        }
    }

    /// The bytes a file of this kind starts with, checked before anything else is read.
    pub const fn magic(self) -> Option<&'static [u8]> {
        match self {
            FileKind::McapLog => Some(b"\x89MCAP0\r\n"),
            _ => None,
        }
    }
}

/// What a path is, when it is not a regular file (for messages).
fn describe(ft: std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if ft.is_fifo() {
            return "a FIFO";
        }
        if ft.is_char_device() {
            return "a character device";
        }
        if ft.is_block_device() {
            return "a block device";
        }
        if ft.is_socket() {
            return "a socket";
        }
    }
    if ft.is_dir() {
        "a directory"
    } else {
        "not a regular file"
    }
}

/// Opens `path` for reading without blocking on a FIFO.
pub(crate) fn open_nonblocking(path: &Path) -> io::Result<File> {
    let mut opts = OpenOptions::new();
    opts.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        // Opening a FIFO for reading blocks until a writer appears; O_NONBLOCK does not.
        opts.custom_flags(libc::O_NONBLOCK);
    }
    opts.open(path)
}

/// The bytes of input files that the run's workers may hold at once, whatever `--jobs`:
/// 512 MiB. A file larger than that (up to its kind's [`FileKind::max_bytes`]) is read alone.
/// Without it, eight workers reading eight sparse 1000 MiB `metric_info.json` files (40 KB on
/// disk) held 7 GB.
pub const BYTES_IN_FLIGHT: u64 = 512 * MIB;

/// The run-wide count of input bytes held ([`read_input_held`]).
struct Budget {
    used: std::sync::Mutex<u64>,
    freed: std::sync::Condvar,
}

static BUDGET: Budget = Budget {
    used: std::sync::Mutex::new(0),
    freed: std::sync::Condvar::new(),
};

impl Budget {
    /// Waits until `n` bytes (at most [`BYTES_IN_FLIGHT`]) fit, and takes them.
    fn take(&self, n: u64) -> u64 {
        let n = n.min(BYTES_IN_FLIGHT);
        let mut used = self.used.lock().unwrap_or_else(|e| e.into_inner());
        while *used + n > BYTES_IN_FLIGHT && *used > 0 {
            used = self.freed.wait(used).unwrap_or_else(|e| e.into_inner());
        }
        *used += n;
        n
    }

    /// Counts `n` more bytes without waiting (a file that grew while it was read: waiting
    /// while holding could deadlock two such readers).
    fn add(&self, n: u64) {
        *self.used.lock().unwrap_or_else(|e| e.into_inner()) += n;
    }

    fn give_back(&self, n: u64) {
        let mut used = self.used.lock().unwrap_or_else(|e| e.into_inner());
        *used = used.saturating_sub(n);
        self.freed.notify_all();
    }
}

/// The bytes of an input file, counted against the run's [`BYTES_IN_FLIGHT`] until dropped.
#[derive(Debug)]
pub struct HeldBytes {
    bytes: Vec<u8>,
    held: u64,
}

impl std::ops::Deref for HeldBytes {
    type Target = [u8];
    fn deref(&self) -> &[u8] {
        &self.bytes
    }
}

impl Drop for HeldBytes {
    fn drop(&mut self) {
        BUDGET.give_back(self.held);
    }
}

/// [`read_input`] for files that many workers read at once (`metric_info.json`,
/// `infractions.json`): the read first waits until the file's size fits in
/// [`BYTES_IN_FLIGHT`] with the bytes other workers hold, and the bytes stay counted until the
/// result is dropped (parse before dropping it). Memory for input bytes is so bounded whatever
/// `--jobs` and however large the files claim to be.
///
/// ```
/// use monitor_host::input::read::{read_input_held, FileKind};
/// let dir = tempfile::tempdir()?;
/// let p = dir.path().join("metric_info.json");
/// std::fs::write(&p, "{}")?;
/// assert_eq!(&*read_input_held(&p, FileKind::MetricInfo)?, b"{}");
/// # Ok::<(), std::io::Error>(())
/// ```
///
/// # Errors
/// As [`read_input`].
pub fn read_input_held(path: &Path, kind: FileKind) -> io::Result<HeldBytes> {
    let file = open_regular(path)?;
    let size = file.metadata()?.len();
    let held = BUDGET.take(size);
    // Counted from here: an error below gives the bytes back.
    let mut out = HeldBytes {
        bytes: Vec::new(),
        held,
    };
    out.bytes = read_bounded(file, size, kind)?;
    let len = out.bytes.len() as u64;
    if len > out.held {
        BUDGET.add(len - out.held);
        out.held = len;
    }
    Ok(out)
}

/// An input file opened for streaming: a regular file (opened without blocking), at most its
/// kind's [`FileKind::max_bytes`] long, starting with its kind's [`FileKind::magic`]. The
/// reader reads from the start (the magic included); [`OpenedInput::take`] bounds what it reads
/// to the limit + 1, whatever the file does after the check.
///
/// ```
/// use monitor_host::input::read::{open_input, FileKind};
/// let dir = tempfile::tempdir()?;
/// let p = dir.path().join("drive.mcap");
/// std::fs::write(&p, b"TOPSECRET")?;
/// let e = open_input(&p, FileKind::McapLog).unwrap_err();
/// // The file's bytes are never printed: only what was expected.
/// assert!(!e.to_string().contains("TOP"), "{e}");
/// # Ok::<(), std::io::Error>(())
/// ```
///
/// # Errors
/// As [`read_input`]; a file that does not start with the magic is
/// [`io::ErrorKind::InvalidData`], with a hint when it is a sqlite3 file (a rosbag2 `.db3`).
pub fn open_input(path: &Path, kind: FileKind) -> io::Result<OpenedInput> {
    let mut file = open_regular(path)?;
    let size = file.metadata()?.len();
    let limit = kind.max_bytes();
    if size > limit {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!(
                "{size} bytes, over the {} MiB limit for a {}",
                limit / MIB,
                kind.name()
            ),
        ));
    }
    if let Some(magic) = kind.magic() {
        use std::io::{Seek, SeekFrom};
        let mut head = vec![0u8; magic.len().max(16)];
        let got = read_up_to(&mut file, &mut head)?;
        if !head[..got].starts_with(magic) {
            let hint = if head[..got].starts_with(b"SQLite format 3") {
                ": it is a sqlite3 database (rosbag2's .db3 storage); convert it with \
                 `ros2 bag convert` to MCAP"
            } else {
                ""
            };
            return Err(io::Error::new(
                io::ErrorKind::InvalidData,
                format!(
                    "not an {}: it does not start with the magic {}{hint}",
                    kind.name(),
                    magic
                        .iter()
                        .map(|b| format!("{b:02x}"))
                        .collect::<Vec<_>>()
                        .join(" ")
                ),
            ));
        }
        file.seek(SeekFrom::Start(0))?;
    }
    Ok(OpenedInput { file, size, limit })
}

/// A file opened by [`open_input`].
#[derive(Debug)]
pub struct OpenedInput {
    file: File,
    /// Its size when opened, bytes.
    pub size: u64,
    limit: u64,
}

impl OpenedInput {
    /// The file, reading at most its kind's limit + 1 bytes (a file that grows after the check
    /// is cut there, and the reader sees a file over the limit).
    pub fn take(self) -> io::Take<File> {
        self.file.take(self.limit + 1)
    }
}

/// Reads until `buf` is full or the end of the file; returns the bytes read.
pub(crate) fn read_up_to(r: &mut impl Read, buf: &mut [u8]) -> io::Result<usize> {
    let mut got = 0;
    while got < buf.len() {
        match r.read(&mut buf[got..]) {
            Ok(0) => break,
            Ok(n) => got += n,
            Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
    Ok(got)
}

/// Bytes of the run's [`BYTES_IN_FLIGHT`] held by a streaming reader (an MCAP log's chunk)
/// until dropped.
#[derive(Debug)]
pub struct Hold(u64);

impl Hold {
    /// Waits until `n` bytes fit in the run's budget with what other workers hold, and holds
    /// them.
    pub fn take(n: u64) -> Hold {
        Hold(BUDGET.take(n))
    }
}

impl Drop for Hold {
    fn drop(&mut self) {
        BUDGET.give_back(self.0);
    }
}

/// Opens `path` for reading without blocking and refuses anything but a regular file.
fn open_regular(path: &Path) -> io::Result<File> {
    let file = open_nonblocking(path)?;
    let meta = file.metadata()?;
    if !meta.is_file() {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!(
                "{}, not a regular file (sds reads only regular files)",
                describe(meta.file_type())
            ),
        ));
    }
    Ok(file)
}

/// Reads a whole input file of kind `kind`, without a leading UTF-8 byte order mark.
///
/// # Errors
/// The I/O error; or, as [`io::ErrorKind::InvalidInput`], a path that is not a regular file (a
/// FIFO, a device, a directory, a socket) or a file larger than [`FileKind::max_bytes`]. The
/// message does not repeat the path: callers name it.
pub fn read_input(path: &Path, kind: FileKind) -> io::Result<Vec<u8>> {
    let file = open_regular(path)?;
    let size = file.metadata()?.len();
    read_bounded(file, size, kind)
}

/// Reads `file` (of `size` bytes when opened) whole, refusing more than the kind's limit.
fn read_bounded(file: File, size: u64, kind: FileKind) -> io::Result<Vec<u8>> {
    let limit = kind.max_bytes();
    let too_large = |size: u64| {
        io::Error::new(
            io::ErrorKind::InvalidInput,
            format!(
                "{size} bytes or more, over the {} MiB limit for a {}",
                limit / MIB,
                kind.name()
            ),
        )
    };
    if size > limit {
        return Err(too_large(size));
    }
    let mut bytes = Vec::with_capacity(size as usize);
    // The file may grow after the check: never read more than the limit + 1.
    file.take(limit + 1).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > limit {
        return Err(too_large(bytes.len() as u64));
    }
    // A UTF-8 byte order mark (Windows editors write one) is not part of the JSON or XML.
    if bytes.starts_with(BOM) {
        bytes.drain(..BOM.len());
    }
    Ok(bytes)
}

/// The UTF-8 byte order mark, skipped at the start of every input file.
const BOM: &[u8] = b"\xEF\xBB\xBF";

/// [`read_input`] as UTF-8 text.
///
/// # Errors
/// As [`read_input`], or [`io::ErrorKind::InvalidData`] for invalid UTF-8.
pub fn read_input_text(path: &Path, kind: FileKind) -> io::Result<String> {
    String::from_utf8(read_input(path, kind)?)
        .map_err(|e| io::Error::new(io::ErrorKind::InvalidData, e.utf8_error()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn limits_grow_with_the_real_sizes() {
        assert!(FileKind::Labels.max_bytes() < FileKind::Results.max_bytes());
        assert!(FileKind::Results.max_bytes() < FileKind::MetricInfo.max_bytes());
    }

    #[test]
    fn held_bytes_are_given_back() {
        // A budget of its own: the run-wide one is shared with the other tests.
        let budget = Budget {
            used: std::sync::Mutex::new(0),
            freed: std::sync::Condvar::new(),
        };
        assert_eq!(budget.take(1000), 1000);
        assert_eq!(*budget.used.lock().unwrap(), 1000);
        budget.give_back(1000);
        assert_eq!(*budget.used.lock().unwrap(), 0);
        // A file larger than the whole budget takes all of it (it is read alone).
        assert_eq!(budget.take(u64::MAX), BYTES_IN_FLIGHT);
        budget.give_back(BYTES_IN_FLIGHT);
        // Through the reader: the bytes are held until dropped, and a missing file is an error.
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("m.json");
        std::fs::write(&p, vec![b' '; 1000]).unwrap();
        let held = read_input_held(&p, FileKind::MetricInfo).unwrap();
        assert_eq!(held.held, 1000);
        drop(held);
        assert!(read_input_held(&dir.path().join("none"), FileKind::MetricInfo).is_err());
    }

    #[test]
    fn a_byte_order_mark_is_skipped() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("r.json");
        std::fs::write(&p, b"\xEF\xBB\xBF{}").unwrap();
        assert_eq!(read_input(&p, FileKind::Results).unwrap(), b"{}");
    }

    #[test]
    fn missing_file_is_an_io_error() {
        let dir = tempfile::tempdir().unwrap();
        let e = read_input(&dir.path().join("nope"), FileKind::Results).unwrap_err();
        assert_eq!(e.kind(), io::ErrorKind::NotFound);
    }
}
