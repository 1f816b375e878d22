//! The JSON rendering of the report (docs/SCORE.md §13): pretty-printed, keys in the
//! model's field order, one trailing newline.

use crate::model::report::Report;

/// The report as pretty-printed JSON with a trailing newline.
///
/// The text is measured first and written into a buffer of exactly its size: a growing buffer
/// would reach twice the report's size (and hold both halves while it grows), the largest
/// allocation of a long run.
///
/// # Errors
/// Only if serialisation fails, which the report's types rule out.
pub fn json(report: &Report) -> Result<Vec<u8>, serde_json::Error> {
    let mut size = Counted(0);
    serde_json::to_writer_pretty(&mut size, report)?;
    let mut v = Vec::with_capacity(size.0 + 1);
    serde_json::to_writer_pretty(&mut v, report)?;
    v.push(b'\n');
    Ok(v)
}

/// A writer that only counts the bytes written to it.
struct Counted(usize);

impl std::io::Write for Counted {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.0 += buf.len();
        Ok(buf.len())
    }

    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// [`json`], written to `out` as it is rendered (the same bytes), so that a large report is
/// never held whole as text.
///
/// # Errors
/// What `out` returns.
pub fn write(report: &Report, out: &mut dyn std::io::Write) -> std::io::Result<()> {
    serde_json::to_writer_pretty(&mut *out, report)?;
    out.write_all(b"\n")
}
