//! The temporary and backup files of a write (docs/RELIABILITY.md, "Output"): named beside the
//! file they stand for, created `O_EXCL` with the umask's mode.

use std::fs::{File, OpenOptions};
use std::os::unix::fs::OpenOptionsExt;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

/// A unique name for a temporary or backup file in the folder of the file it stands for; short,
/// so that it fits wherever the file's own name fits.
pub(crate) fn scratch_name(dir: &Path, what: &str) -> PathBuf {
    static NEXT: AtomicUsize = AtomicUsize::new(0);
    let n = NEXT.fetch_add(1, Ordering::Relaxed);
    dir.join(format!(".sds-{}-{n}.{what}", std::process::id()))
}

/// Creates the temporary file `tmp`: `create_new` (O_EXCL) never follows a link at its name,
/// and 0666 on creation lets the kernel apply the umask, as a shell redirection does.
pub(crate) fn create(tmp: &Path) -> std::io::Result<File> {
    OpenOptions::new()
        .write(true)
        .create_new(true)
        .mode(0o666)
        .custom_flags(libc::O_NOFOLLOW | libc::O_CLOEXEC)
        .open(tmp)
}

/// The folder of `path` (`.` for a bare name).
pub(crate) fn folder_of(path: &Path) -> &Path {
    path.parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."))
}
