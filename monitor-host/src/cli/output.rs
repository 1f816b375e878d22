//! Writing a rendering: to standard output, or atomically to a regular file.
//!
//! The rules (`docs/RELIABILITY.md`, "Output"):
//! - `-o` writes only regular files. A path that exists and is anything else (a device such as
//!   `/dev/null`, a FIFO, `/dev/stdout`, a directory, a socket) is refused with a message: it is
//!   never replaced by a rename. Standard output (no `-o`) is the way to write to those.
//! - `-o` never names one of the run's inputs (compared by device and inode, so links and other
//!   spellings of the same file are caught).
//! - A symbolic link as `-o` stays a link: the file it points to is replaced.
//! - The new file gets the umask's mode (`0666 & !umask`, as a shell redirection would); an
//!   existing file keeps its mode.
//! - The temporary file sits beside the output (`.<name>.sds-<pid>.tmp`) and is removed on
//!   SIGINT / SIGTERM ([`install_signal_cleanup`]) and on every error.
//! - A closed standard output is an error, never a silently lost report.

use std::fs::{self, OpenOptions};
use std::io::Write;
use std::os::unix::fs::{MetadataExt, OpenOptionsExt, PermissionsExt};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;

use anyhow::{bail, Context, Result};

/// The temporary file being written, removed by the signal thread.
static PENDING: Mutex<Option<PathBuf>> = Mutex::new(None);

/// Standard output was closed when the process started.
static STDOUT_CLOSED: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Records whether descriptor 1 is closed, before Rust's runtime starts: the runtime then fills
/// a closed 0, 1 or 2 with `/dev/null` (so no input file can take its number), which would make
/// a closed standard output look like `> /dev/null` and lose the report without a word.
#[cfg(target_os = "linux")]
#[allow(unsafe_code)]
#[used]
#[link_section = ".init_array"]
static CHECK_STDOUT_AT_START: extern "C" fn() = check_stdout_at_start;

#[cfg(target_os = "linux")]
#[allow(unsafe_code)]
extern "C" fn check_stdout_at_start() {
    // SAFETY: F_GETFD on a descriptor number has no memory effects.
    if unsafe { libc::fcntl(libc::STDOUT_FILENO, libc::F_GETFD) } == -1 {
        STDOUT_CLOSED.store(true, std::sync::atomic::Ordering::Relaxed);
    }
}

/// Test seam: milliseconds to wait between writing the temporary file and renaming it, so that
/// the signal tests can interrupt the final write. Not documented for users.
const DELAY_ENV: &str = "SDS_TEST_WRITE_DELAY_MS";

/// Set by [`defer_signals`]: the first SIGINT / SIGTERM only sets [`stop_requested`].
static DEFER: AtomicBool = AtomicBool::new(false);
/// A deferred signal arrived.
static STOP: AtomicBool = AtomicBool::new(false);
/// A signal this soon after the deferred one is the same request, not a second one.
const REPEAT: std::time::Duration = std::time::Duration::from_secs(2);

/// From now on the first SIGINT / SIGTERM asks the program to stop ([`stop_requested`]) instead
/// of ending it (`sds watch` writes its final report first); another one within 2 s of it is
/// the same request (ignored), a later one ends the program as before.
pub fn defer_signals() {
    DEFER.store(true, Ordering::SeqCst);
}

/// A SIGINT or SIGTERM arrived since [`defer_signals`].
pub fn stop_requested() -> bool {
    STOP.load(Ordering::SeqCst)
}

/// Starts a thread that, on SIGINT or SIGTERM, removes the temporary output file (if one is
/// being written) and then dies of the signal as it would have without the handler.
pub fn install_signal_cleanup() -> Result<()> {
    use signal_hook::consts::{SIGINT, SIGTERM};
    let mut signals = signal_hook::iterator::Signals::new([SIGINT, SIGTERM])
        .context("cannot install the SIGINT / SIGTERM handler")?;
    std::thread::spawn(move || {
        let mut first: Option<std::time::Instant> = None;
        for sig in signals.forever() {
            // `sds watch` stops on the first signal after its final report; a second one kills,
            // unless it comes within REPEAT of the first: coreutils' `timeout` sends its signal
            // twice at once (to the child, then to its process group), which is one request.
            if DEFER.load(Ordering::SeqCst) {
                if !STOP.swap(true, Ordering::SeqCst) {
                    first = Some(std::time::Instant::now());
                    continue;
                }
                if first.is_some_and(|t| t.elapsed() < REPEAT) {
                    continue;
                }
            }
            let pending = PENDING.lock().unwrap_or_else(|e| e.into_inner());
            if let Some(p) = pending.as_ref() {
                let _ = fs::remove_file(p);
            }
            // Die of the signal while holding the lock: the writer cannot start a new file.
            let _ = signal_hook::low_level::emulate_default_handler(sig);
            std::process::exit(128 + sig);
        }
    });
    Ok(())
}

/// Writes every collision trace of the report into `dir` (created if needed) as CSV and SVG,
/// under unique names ([`crate::report::trace_csv::unique_stems`]); returns the number of
/// traces. All or nothing: when one file cannot be written, the files this call wrote are
/// removed again and the error names the file.
pub fn write_traces(
    dir: &Path,
    report: &crate::report::Report,
    inputs: &[PathBuf],
) -> Result<usize> {
    use crate::report::{figure, trace_csv};
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let traces: Vec<(usize, &crate::route::trace::CollisionTrace)> = report
        .routes
        .iter()
        .enumerate()
        .flat_map(|(i, r)| r.traces.iter().map(move |t| (i, t)))
        .collect();
    let stems = trace_csv::unique_stems(&traces);
    let mut files: Vec<(PathBuf, Vec<u8>)> = Vec::new();
    for ((_, t), stem) in traces.iter().zip(&stems) {
        files.push((
            dir.join(format!("{stem}.csv")),
            trace_csv::csv(t).into_bytes(),
        ));
        files.push((dir.join(format!("{stem}.svg")), figure::svg(t).into_bytes()));
    }
    write_all_or_nothing(&files, inputs).map_err(|e| {
        e.context(format!(
            "--traces {}: no trace written and no report (fix the folder, or leave out --traces)",
            dir.display()
        ))
    })?;
    Ok(traces.len())
}

/// Writes each `(path, bytes)` in order; when one cannot be written, removes those this call
/// wrote and returns that error (the traces and the pictures: all or nothing).
fn write_all_or_nothing(files: &[(PathBuf, Vec<u8>)], inputs: &[PathBuf]) -> Result<()> {
    let mut written: Vec<&Path> = Vec::new();
    for (path, bytes) in files {
        if let Err(e) = write_output(Some(path), bytes, inputs) {
            for p in &written {
                let _ = fs::remove_file(p);
            }
            return Err(e);
        }
        written.push(path);
    }
    Ok(())
}

/// Writes the run's pictures into `dir` (created if needed): `decomposition.svg` (the
/// waterfall from DS to SDS; left out when the run has no decomposition) and `routes.svg` (DS
/// and DS_safe per route). Returns the names written. All or nothing, as [`write_traces`].
pub fn write_figures(
    dir: &Path,
    report: &crate::report::Report,
    inputs: &[PathBuf],
) -> Result<Vec<&'static str>> {
    use crate::report::{route_chart, waterfall};
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let mut names = Vec::new();
    let mut files: Vec<(PathBuf, Vec<u8>)> = Vec::new();
    let decomposition = report.summary.scores.decomposition.as_ref();
    for (name, svg) in [
        ("decomposition.svg", decomposition.map(waterfall::svg)),
        ("routes.svg", Some(route_chart::svg(&report.routes))),
    ] {
        if let Some(svg) = svg {
            names.push(name);
            files.push((dir.join(name), svg.into_bytes()));
        }
    }
    write_all_or_nothing(&files, inputs).map_err(|e| {
        e.context(format!(
            "--figures {}: no figure written and no report (fix the folder, or leave out --figures)",
            dir.display()
        ))
    })?;
    Ok(names)
}

fn describe(ft: fs::FileType) -> &'static str {
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

/// Refuses an output path that exists and is not a regular file, or that is one of `inputs`.
/// Returns the path to replace (a link resolved to its target) and the mode to keep, if any.
fn check_target(path: &Path, inputs: &[PathBuf]) -> Result<(PathBuf, Option<u32>)> {
    let meta = match fs::metadata(path) {
        Ok(m) => m,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            // A dangling link: writing would create its target somewhere unexpected.
            if fs::symlink_metadata(path).is_ok() {
                bail!(
                    "{}: a symbolic link to a missing file; sds writes only regular files",
                    path.display()
                );
            }
            return Ok((path.to_path_buf(), None));
        }
        Err(e) => return Err(e).with_context(|| format!("cannot inspect {}", path.display())),
    };
    if !meta.is_file() {
        bail!(
            "{}: {}, not a regular file; sds writes the report only to regular files \
             (leave out -o to write to standard output, e.g. `sds score ... > {}`)",
            path.display(),
            describe(meta.file_type()),
            path.display()
        );
    }
    for input in inputs {
        if let Ok(m) = fs::metadata(input) {
            if m.dev() == meta.dev() && m.ino() == meta.ino() {
                bail!(
                    "{}: this is one of the run's inputs ({}); choose another output path",
                    path.display(),
                    input.display()
                );
            }
        }
    }
    let target =
        fs::canonicalize(path).with_context(|| format!("cannot resolve {}", path.display()))?;
    Ok((target, Some(meta.permissions().mode() & 0o7777)))
}

/// Writes `bytes` to `path` atomically (a temporary file in the same folder, then a rename), or
/// to standard output. `inputs` are the run's input files: `path` must not be one of them.
pub fn write_output(path: Option<&Path>, bytes: &[u8], inputs: &[PathBuf]) -> Result<()> {
    let Some(path) = path else {
        return write_stdout(bytes);
    };
    let (target, keep_mode) = check_target(path, inputs)?;
    let dir = target
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = target
        .file_name()
        .with_context(|| format!("{}: not a file name", path.display()))?;
    let tmp = dir.join(format!(
        ".{}.sds-{}.tmp",
        name.to_string_lossy(),
        std::process::id()
    ));
    let result = write_temp_then_rename(&tmp, &target, bytes, keep_mode);
    if result.is_err() {
        let _guard = PENDING.lock().unwrap_or_else(|e| e.into_inner());
        let _ = fs::remove_file(&tmp);
    }
    *PENDING.lock().unwrap_or_else(|e| e.into_inner()) = None;
    result.with_context(|| format!("cannot write {}", path.display()))
}

/// Creation and rename happen under the [`PENDING`] lock, so the signal thread either removes a
/// finished temporary file or stops the process before one exists: none is left behind.
fn write_temp_then_rename(
    tmp: &Path,
    target: &Path,
    bytes: &[u8],
    keep_mode: Option<u32>,
) -> Result<()> {
    let mut f = {
        let mut pending = PENDING.lock().unwrap_or_else(|e| e.into_inner());
        *pending = Some(tmp.to_path_buf());
        // 0666 on creation: the kernel applies the umask, as for a shell redirection.
        OpenOptions::new()
            .write(true)
            .create_new(true)
            .mode(0o666)
            .open(tmp)
            .with_context(|| format!("cannot create {}", tmp.display()))?
    };
    if let Some(mode) = keep_mode {
        f.set_permissions(fs::Permissions::from_mode(mode))?;
    }
    f.write_all(bytes)?;
    f.sync_all()?;
    drop(f);
    if let Some(ms) = std::env::var(DELAY_ENV).ok().and_then(|v| v.parse().ok()) {
        std::thread::sleep(std::time::Duration::from_millis(ms));
    }
    let mut pending = PENDING.lock().unwrap_or_else(|e| e.into_inner());
    // Checked again just before the rename: a device or FIFO that appeared at the path since
    // `check_target` (as root, a rename would turn `/dev/null` into a regular file) is refused.
    if let Ok(m) = fs::symlink_metadata(target) {
        if !m.is_file() {
            bail!(
                "{}: became {} while the report was written; not replaced",
                target.display(),
                describe(m.file_type())
            );
        }
    }
    fs::rename(tmp, target)?;
    *pending = None;
    Ok(())
}

/// Standard output, refusing a closed one (Rust's standard library would swallow the EBADF).
fn write_stdout(bytes: &[u8]) -> Result<()> {
    if STDOUT_CLOSED.load(std::sync::atomic::Ordering::Relaxed) {
        bail!("standard output is closed: the report cannot be written (use -o FILE)");
    }
    let mut out = std::io::stdout().lock();
    out.write_all(bytes)
        .and_then(|()| out.flush())
        .context("cannot write the report to standard output")
}
