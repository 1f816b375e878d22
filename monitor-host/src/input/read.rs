//! The one way an input file is read: regular files only, never more than a size bound per file
//! kind. Every reader of `input/` goes through [`read_input`]; none opens files itself.
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

fn open_nonblocking(path: &Path) -> io::Result<File> {
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

/// Reads a whole input file of kind `kind`, without a leading UTF-8 byte order mark.
///
/// # Errors
/// The I/O error; or, as [`io::ErrorKind::InvalidInput`], a path that is not a regular file (a
/// FIFO, a device, a directory, a socket) or a file larger than [`FileKind::max_bytes`]. The
/// message does not repeat the path: callers name it.
pub fn read_input(path: &Path, kind: FileKind) -> io::Result<Vec<u8>> {
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
    if meta.len() > limit {
        return Err(too_large(meta.len()));
    }
    let mut bytes = Vec::with_capacity(meta.len() as usize);
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
