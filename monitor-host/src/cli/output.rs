//! Writing a rendering: to standard output, or atomically to a file.

use std::io::Write;
use std::path::Path;

use anyhow::{Context, Result};

/// Writes `bytes` to `path` atomically (a temporary file in the same folder, then a rename),
/// or to standard output.
pub fn write_output(path: Option<&Path>, bytes: &[u8]) -> Result<()> {
    match path {
        None => {
            let mut out = std::io::stdout().lock();
            out.write_all(bytes)?;
            out.flush()?;
        }
        Some(p) => {
            let dir = p
                .parent()
                .filter(|d| !d.as_os_str().is_empty())
                .unwrap_or(Path::new("."));
            let mut tmp = tempfile::NamedTempFile::new_in(dir)
                .with_context(|| format!("cannot create a file in {}", dir.display()))?;
            tmp.write_all(bytes)?;
            tmp.as_file().sync_all()?;
            tmp.persist(p)
                .with_context(|| format!("cannot write {}", p.display()))?;
        }
    }
    Ok(())
}

/// Writes every collision trace of the report into `dir` (created if needed) as CSV and SVG;
/// returns the number of traces.
pub fn write_traces(dir: &Path, report: &crate::report::Report) -> Result<usize> {
    use crate::report::{figure, trace_csv};
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let mut n = 0;
    for t in report.routes.iter().flat_map(|r| &r.traces) {
        let stem = trace_csv::file_stem(t);
        write_output(
            Some(&dir.join(format!("{stem}.csv"))),
            trace_csv::csv(t).as_bytes(),
        )?;
        write_output(
            Some(&dir.join(format!("{stem}.svg"))),
            figure::svg(t).as_bytes(),
        )?;
        n += 1;
    }
    Ok(n)
}
