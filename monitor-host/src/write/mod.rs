//! Writing files safely (docs/RELIABILITY.md, "Output"): the rules every front end follows
//! when it puts a report, a table, a figure or a trace on disk, so that `sds` and the Python
//! package write the same way.
//!
//! - A file is written to a temporary file in its folder (created `O_EXCL`, so never through a
//!   link at that name either), then renamed over its name ([`FileSet::place`],
//!   [`FileSet::write_file`]).
//! - At a name the tool chose, a symbolic link is refused, never followed, and so is anything
//!   but a regular file ([`refuse`]). A file the user named (`-o`, the rerun list) may be a
//!   link: the file it points to is replaced, and it keeps its mode.
//! - Nothing is written over one of the run's inputs (compared by device and inode).
//! - A set of files is all or nothing: a file replaced is kept as a hard-linked backup until
//!   [`FileSet::commit`]; [`FileSet::roll_back`] removes the files written and the folders
//!   created and puts back the files replaced.
//!
//! The front ends keep only their process concerns: the command line its signals and
//! standard output, the Python package its exceptions.

pub mod error;
pub mod file_set;
pub mod refuse;
mod scratch;

pub use error::WriteError;
pub use file_set::{FileSet, Hooks};
pub use refuse::{check_folder, refuse_clash, refuse_named_clash, BadOutputPath, OutputClash};
