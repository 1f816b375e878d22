//! The paths a write refuses (docs/RELIABILITY.md, "Output"): a link or anything but a regular
//! file at a name the tool chose, one of the run's inputs, an output that is another output's
//! path, a folder that cannot hold the file.

use std::fs;
use std::os::unix::fs::{MetadataExt, PermissionsExt};
use std::path::{Path, PathBuf};

use super::error::{Context as _, WriteError};
use super::scratch::folder_of;

/// What a file that is not a regular file is, as a message says it.
pub(crate) fn describe(ft: fs::FileType) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    if ft.is_dir() {
        "a directory"
    } else if ft.is_fifo() {
        "a FIFO"
    } else if ft.is_char_device() {
        "a character device"
    } else if ft.is_block_device() {
        "a block device"
    } else if ft.is_socket() {
        "a socket"
    } else {
        "not a regular file"
    }
}

/// Refuses what sits at `path`, a name the tool chose (a table, a figure, a trace): a symbolic
/// link (never followed) or anything but a regular file; returns whether a regular file is
/// there. A front end may call it on every name of a set before writing any.
///
/// ```
/// let dir = tempfile::tempdir().unwrap();
/// let link = dir.path().join("routes.csv");
/// std::os::unix::fs::symlink("/etc/passwd", &link).unwrap();
/// let e = monitor_host::write::refuse::refuse_unsafe(&link).unwrap_err();
/// assert!(e.to_string().ends_with("routes.csv: a symbolic link; sds never writes through a \
///          link at a name it chose (remove the link, or choose another folder)"));
/// ```
///
/// # Errors
/// The refusal, naming the path; a path that cannot be inspected.
pub fn refuse_unsafe(path: &Path) -> Result<bool, WriteError> {
    match fs::symlink_metadata(path) {
        Ok(m) if m.file_type().is_symlink() => Err(WriteError::new(format!(
            "{}: a symbolic link; sds never writes through a link at a name it chose \
             (remove the link, or choose another folder)",
            path.display()
        ))),
        Ok(m) if !m.is_file() => Err(WriteError::new(format!(
            "{}: {}, not a regular file; sds writes only regular files",
            path.display(),
            describe(m.file_type())
        ))),
        Ok(_) => Ok(true),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(false),
        Err(e) => Err(WriteError::caused(
            format!("cannot inspect {}", path.display()),
            e,
        )),
    }
}

/// Refuses a path whose file (`meta`) is one of `inputs` (compared by device and inode, so
/// links and other spellings of the same file are caught).
pub(crate) fn refuse_input(
    path: &Path,
    meta: &fs::Metadata,
    inputs: &[PathBuf],
) -> Result<(), WriteError> {
    for input in inputs {
        if let Ok(m) = fs::metadata(input) {
            if m.dev() == meta.dev() && m.ino() == meta.ino() {
                return Err(WriteError::new(format!(
                    "{}: this is one of the run's inputs ({}); choose another output path",
                    path.display(),
                    input.display()
                )));
            }
        }
    }
    Ok(())
}

/// Refuses a path the user named (`-o`) that exists and is not a regular file, or that is one
/// of `inputs`. Returns the path to replace (a link resolved to its target) and the mode to
/// keep, if any.
pub(crate) fn check_target(
    path: &Path,
    inputs: &[PathBuf],
) -> Result<(PathBuf, Option<u32>), WriteError> {
    let meta = match fs::metadata(path) {
        Ok(m) => m,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            // A dangling link: writing would create its target somewhere unexpected.
            if fs::symlink_metadata(path).is_ok() {
                return Err(WriteError::new(format!(
                    "{}: a symbolic link to a missing file; sds writes only regular files",
                    path.display()
                )));
            }
            return Ok((path.to_path_buf(), None));
        }
        Err(e) => {
            return Err(WriteError::caused(
                format!("cannot inspect {}", path.display()),
                e,
            ))
        }
    };
    if !meta.is_file() {
        return Err(WriteError::new(format!(
            "{}: {}, not a regular file; sds writes the report only to regular files \
             (leave out -o to write to standard output, e.g. `sds score ... > {}`)",
            path.display(),
            describe(meta.file_type()),
            path.display()
        )));
    }
    refuse_input(path, &meta, inputs)?;
    let target =
        fs::canonicalize(path).context_with(|| format!("cannot resolve {}", path.display()))?;
    Ok((target, Some(meta.permissions().mode() & 0o7777)))
}

/// `-o` (or another output option: `option`) names a file the run writes itself (a figure, a
/// trace, the rerun list): one would be written over the other.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{option} {out}: this is the path of {what} the run writes ({path}); choose another output path")]
pub struct OutputClash {
    /// `-o`, `--rerun-list`, `--rerun-xml`.
    pub option: &'static str,
    /// The `-o` path.
    pub out: String,
    /// `a figure`, `a trace`, `the rerun list`.
    pub what: String,
    /// The file it is.
    pub path: String,
}

/// Refuses an `-o` that is one of `paths` (the run's own files, `what`): by device and inode
/// when both exist, else by their folders resolved and their names.
///
/// ```
/// use std::path::{Path, PathBuf};
/// let e = monitor_host::write::refuse_clash(Path::new("f/./routes.svg"),
///     &[PathBuf::from("f/routes.svg")], "a figure").unwrap_err();
/// assert_eq!(e.what, "a figure");
/// ```
///
/// # Errors
/// The clash.
pub fn refuse_clash(out: &Path, paths: &[PathBuf], what: &'static str) -> Result<(), OutputClash> {
    refuse_named_clash(out, "-o", paths, what)
}

/// [`refuse_clash`] for the output of another option than `-o`.
///
/// # Errors
/// The clash.
pub fn refuse_named_clash(
    out: &Path,
    option: &'static str,
    paths: &[PathBuf],
    what: &str,
) -> Result<(), OutputClash> {
    let key = place_key(out);
    let meta = fs::metadata(out).ok();
    for p in paths {
        let same_file = meta
            .as_ref()
            .zip(fs::metadata(p).ok())
            .is_some_and(|(a, b)| a.dev() == b.dev() && a.ino() == b.ino());
        if same_file || place_key(p) == key {
            return Err(OutputClash {
                option,
                out: out.display().to_string(),
                what: what.to_string(),
                path: p.display().to_string(),
            });
        }
    }
    Ok(())
}

/// Where `p` is on disk: the file resolved when it exists, else its folder resolved (or, for a
/// folder that does not exist yet, made absolute with `.` and `..` taken out) and its name.
fn place_key(p: &Path) -> PathBuf {
    if let Ok(c) = fs::canonicalize(p) {
        return c;
    }
    let abs = std::env::current_dir().unwrap_or_default().join(p);
    let (Some(parent), Some(name)) = (abs.parent(), abs.file_name()) else {
        return abs;
    };
    let dir = fs::canonicalize(parent).unwrap_or_else(|_| {
        let mut d = PathBuf::new();
        for c in parent.components() {
            match c {
                std::path::Component::CurDir => {}
                std::path::Component::ParentDir => {
                    d.pop();
                }
                c => d.push(c),
            }
        }
        d
    });
    dir.join(name)
}

/// An output path that cannot be written, found before any work (`--rerun-list` in a folder
/// that does not exist, or naming a folder or device).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct BadOutputPath(pub String);

/// Checks, before any work, that `path` can be written as a file the user named: its folder
/// exists and is a folder, and the path is not a folder, device or FIFO.
///
/// ```
/// let e = monitor_host::write::check_folder(std::path::Path::new("/nonexistent/x")).unwrap_err();
/// assert!(e.0.starts_with("its folder /nonexistent cannot be used"));
/// ```
///
/// # Errors
/// What is wrong with the path, without the path (the caller names it with its option).
pub fn check_folder(path: &Path) -> Result<(), BadOutputPath> {
    let dir = folder_of(path);
    match fs::metadata(dir) {
        Ok(m) if m.is_dir() => {}
        Ok(m) => {
            return Err(BadOutputPath(format!(
                "its folder {} is {}, not a folder",
                dir.display(),
                describe(m.file_type())
            )))
        }
        Err(e) => {
            return Err(BadOutputPath(format!(
                "its folder {} cannot be used ({e}); create it first, or choose another path",
                dir.display()
            )))
        }
    }
    match fs::metadata(path) {
        Ok(m) if !m.is_file() => Err(BadOutputPath(format!(
            "{}, not a regular file; sds writes only regular files",
            describe(m.file_type())
        ))),
        _ => Ok(()),
    }
}
