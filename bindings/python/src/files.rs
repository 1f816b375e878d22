//! `FileSet` and `refuse_unsafe`: the library's write rules ([`monitor_host::write`],
//! docs/RELIABILITY.md "Output") for the files the package names itself (`sds.to_parquet`'s
//! tables, the reports `sds.log` copies into a TensorBoard folder): the same temporary file,
//! refusals, backups and all-or-nothing as the `sds` command's `--tables`.

use std::os::fd::AsRawFd;
use std::path::PathBuf;

use monitor_host::write::{self, WriteError};
use pyo3::prelude::*;

use crate::errors::IoError;

/// A write refused or failed, as the package raises it.
fn io_error(e: &WriteError) -> PyErr {
    IoError::new_err(monitor_host::error::message(e))
}

/// The files written into `folder` (created with its missing parents), kept by `commit`,
/// undone by `roll_back` (`sds._files.FileSet` is the context manager over it).
#[pyclass(module = "sds._sds")]
pub struct FileSet {
    set: write::FileSet,
}

#[pymethods]
impl FileSet {
    /// Creates `folder` with its missing parents (removed again by `roll_back`).
    #[new]
    fn new(folder: PathBuf) -> PyResult<Self> {
        let set = write::FileSet::new();
        set.create_dir(&folder).map_err(|e| io_error(&e))?;
        Ok(FileSet { set })
    }

    /// Writes `path` through `write`, called with the temporary file's descriptor (open for
    /// writing; the caller must not close it), then renames it over `path`. An exception of
    /// `write` is raised as it is; a refusal or a failed write raises `IoError`.
    fn place(&self, path: PathBuf, write: Bound<'_, PyAny>) -> PyResult<()> {
        let mut raised = None;
        let placed = self.set.place_with(&path, &[], None, &mut |f| {
            write.call1((f.as_raw_fd(),)).map(drop).map_err(|e| {
                raised = Some(e);
                std::io::Error::other("the writer raised")
            })
        });
        match (raised, placed) {
            (Some(e), _) => Err(e),
            (None, r) => r.map_err(|e| io_error(&e)),
        }
    }

    /// Keeps what was written: drops the backups of the replaced files.
    fn commit(&self) {
        self.set.commit();
    }

    /// Removes what was written, puts back what was replaced, removes the folders created.
    fn roll_back(&self) {
        self.set.roll_back();
    }
}

/// Raises `IoError` when `path` is a link or anything but a regular file; returns whether a
/// regular file is there (to refuse a whole set before writing any of it).
#[pyfunction(name = "refuse_unsafe")]
pub fn refuse_special(path: PathBuf) -> PyResult<bool> {
    write::refuse::refuse_unsafe(&path).map_err(|e| io_error(&e))
}
