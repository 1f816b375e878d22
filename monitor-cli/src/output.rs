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

/// What this process has put on disk and not yet committed: the temporary files being written,
/// the files it created, and the files it replaced (each kept as a hard-linked backup until the
/// commit). The signal thread and every error undo exactly this, nothing else ([`roll_back`]).
#[derive(Default)]
struct Undo {
    temps: Vec<PathBuf>,
    created: Vec<PathBuf>,
    replaced: Vec<(PathBuf, PathBuf)>,
    dirs: Vec<PathBuf>,
}

impl Undo {
    const fn new() -> Undo {
        Undo {
            temps: Vec::new(),
            created: Vec::new(),
            replaced: Vec::new(),
            dirs: Vec::new(),
        }
    }

    /// Removes what was created, puts back what was replaced (newest first), removes the
    /// folders created for it when they are empty again.
    fn roll_back(&mut self) {
        for p in self.temps.drain(..) {
            let _ = fs::remove_file(p);
        }
        for p in self.created.drain(..).rev() {
            let _ = fs::remove_file(p);
        }
        for (path, backup) in self.replaced.drain(..).rev() {
            let _ = fs::rename(backup, path);
        }
        for d in self.dirs.drain(..).rev() {
            let _ = fs::remove_dir(d);
        }
    }

    /// Keeps what was written: drops the backups of the replaced files.
    fn commit(&mut self) {
        for (_, backup) in self.replaced.drain(..) {
            let _ = fs::remove_file(backup);
        }
        self.temps.clear();
        self.created.clear();
        self.dirs.clear();
    }
}

/// The files being written, undone by the signal thread.
static PENDING: Mutex<Undo> = Mutex::new(Undo::new());

fn pending() -> std::sync::MutexGuard<'static, Undo> {
    PENDING.lock().unwrap_or_else(|e| e.into_inner())
}

/// Undoes every file written since the last [`commit`] (traces and figures: all or nothing).
pub fn roll_back() {
    pending().roll_back();
}

/// Keeps every file written since the last [`commit`] or [`roll_back`].
pub fn commit() {
    pending().commit();
}

/// A unique name for a temporary or backup file in the folder of the file it stands for; short,
/// so that it fits wherever the file's own name fits.
fn scratch_name(dir: &Path, what: &str) -> PathBuf {
    static NEXT: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let n = NEXT.fetch_add(1, Ordering::Relaxed);
    dir.join(format!(".sds-{}-{n}.{what}", std::process::id()))
}

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
/// Test seam: the final write waits here until the process is signalled, so that the signal
/// tests interrupt it whatever the machine's load (a delay raced the clock). Not documented for
/// users.
const HOLD_ENV: &str = "SDS_TEST_WRITE_HOLD";
/// Test seam: after placing this many traces or figures the run waits until it is signalled, so
/// that the signal tests interrupt the traces half-written whatever the machine's load. Not
/// documented for users.
const PLACE_HOLD_ENV: &str = "SDS_TEST_PLACE_HOLD";

/// Test seams: waits until a signal ends the process.
fn hold_until_signalled() -> ! {
    loop {
        std::thread::sleep(std::time::Duration::from_secs(3600));
    }
}

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

/// Starts a thread that, on SIGINT or SIGTERM, undoes what is being written (the temporary
/// output file; the traces and figures written so far, the files they replaced put back) and
/// then dies of the signal as it would have without the handler.
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
            let mut pending = pending();
            pending.roll_back();
            // Die of the signal while holding the lock: the writer cannot start a new file.
            let _ = signal_hook::low_level::emulate_default_handler(sig);
            std::process::exit(128 + sig);
        }
    });
    Ok(())
}

/// The trace files of the report in `dir`: `(path, contents)`, CSV and SVG per trace, under
/// unique names ([`monitor_host::report::trace_csv::unique_stems`]).
fn trace_files(dir: &Path, report: &monitor_host::report::Report) -> Vec<(PathBuf, Vec<u8>)> {
    use monitor_host::report::{figure, trace_csv};
    let traces: Vec<(usize, &monitor_host::route::trace::CollisionTrace)> = report
        .routes
        .iter()
        .enumerate()
        .flat_map(|(i, r)| r.traces.iter().map(move |t| (i, t)))
        .collect();
    let stems = trace_csv::unique_stems(&traces);
    let mut files = Vec::with_capacity(2 * traces.len());
    for ((_, t), stem) in traces.iter().zip(&stems) {
        files.push((
            dir.join(format!("{stem}.csv")),
            trace_csv::csv(t).into_bytes(),
        ));
        files.push((dir.join(format!("{stem}.svg")), figure::svg(t).into_bytes()));
    }
    files
}

/// The paths `--traces DIR` writes for this report (to refuse an `-o` among them).
pub fn trace_paths(dir: &Path, report: &monitor_host::report::Report) -> Vec<PathBuf> {
    trace_files(dir, report)
        .into_iter()
        .map(|(p, _)| p)
        .collect()
}

/// Writes every collision trace of the report into `dir` (created if needed) as CSV and SVG
/// and returns the number of traces, leaving them to the caller's [`commit`] or [`roll_back`].
/// The names are the tool's: a file there is replaced (and put back on [`roll_back`]), a
/// symbolic link there is refused, never followed (see `place`).
pub fn place_traces(
    dir: &Path,
    report: &monitor_host::report::Report,
    inputs: &[PathBuf],
) -> Result<usize> {
    let files = trace_files(dir, report);
    place_all(dir, &files, inputs).map_err(|e| {
        e.context(format!(
            "--traces {}: no trace written and no report (fix the folder, or leave out --traces)",
            dir.display()
        ))
    })?;
    Ok(files.len() / 2)
}

/// Creates `dir` (recording the folders it created, for [`roll_back`]) and places each file.
fn place_all(dir: &Path, files: &[(PathBuf, Vec<u8>)], inputs: &[PathBuf]) -> Result<()> {
    let mut missing = Vec::new();
    let mut d = Some(dir);
    while let Some(p) = d.filter(|p| !p.as_os_str().is_empty() && fs::symlink_metadata(p).is_err())
    {
        missing.push(p.to_path_buf());
        d = p.parent();
    }
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    pending().dirs.extend(missing.into_iter().rev());
    for (path, bytes) in files {
        place(path, bytes, inputs)?;
    }
    Ok(())
}

/// The figure files of the run: `decomposition.svg` (the waterfall from DS to SDS; left out
/// when the run has no decomposition) and `routes.svg` (DS and DS_safe per route).
fn figure_files(report: &monitor_host::report::Report) -> Vec<(&'static str, Vec<u8>)> {
    use monitor_host::report::{route_chart, waterfall};
    let decomposition = report.summary.scores.decomposition.as_ref();
    [
        ("decomposition.svg", decomposition.map(waterfall::svg)),
        ("routes.svg", Some(route_chart::svg(&report.routes))),
    ]
    .into_iter()
    .filter_map(|(name, svg)| svg.map(|s| (name, s.into_bytes())))
    .collect()
}

/// The names `--figures DIR` may write (to refuse an `-o` among them).
pub const FIGURE_NAMES: [&str; 2] = ["decomposition.svg", "routes.svg"];

/// Writes the run's pictures into `dir` (created if needed) and returns the names written,
/// leaving them to the caller's [`commit`] or [`roll_back`], as [`place_traces`].
pub fn place_figures(
    dir: &Path,
    report: &monitor_host::report::Report,
    inputs: &[PathBuf],
) -> Result<Vec<&'static str>> {
    let named = figure_files(report);
    let names = named.iter().map(|(n, _)| *n).collect();
    let files: Vec<(PathBuf, Vec<u8>)> = named.into_iter().map(|(n, b)| (dir.join(n), b)).collect();
    place_all(dir, &files, inputs).map_err(|e| {
        e.context(format!(
            "--figures {}: no figure written and no report (fix the folder, or leave out --figures)",
            dir.display()
        ))
    })?;
    Ok(names)
}

/// Writes the long tables (`--tables DIR`: `routes.csv`, `events.csv`, `frames.csv`) into `dir`
/// (created if needed), leaving them to the caller's [`commit`] or [`roll_back`], as
/// [`place_traces`].
pub fn place_tables(dir: &Path, named: Vec<(&str, Vec<u8>)>, inputs: &[PathBuf]) -> Result<()> {
    let files: Vec<(PathBuf, Vec<u8>)> = named.into_iter().map(|(n, b)| (dir.join(n), b)).collect();
    place_all(dir, &files, inputs).map_err(|e| {
        e.context(format!(
            "--tables {}: no table written and no report (fix the folder, or leave out --tables)",
            dir.display()
        ))
    })
}

/// Writes `bytes` at `path`, a name the tool chose (a trace, a figure), through a temporary
/// file in the same folder renamed over it: never through a symbolic link (one planted there
/// is refused, and its target stays untouched), never over anything but a regular file that
/// is not an input. A file replaced is kept as a hard-linked backup until [`commit`], so that
/// [`roll_back`] can put it back; a file created is removed by [`roll_back`].
fn place(path: &Path, bytes: &[u8], inputs: &[PathBuf]) -> Result<()> {
    place_mode(path, bytes, inputs, None)
}

/// [`place`], the new file given `keep_mode` (the mode of the file it replaces).
fn place_mode(path: &Path, bytes: &[u8], inputs: &[PathBuf], keep_mode: Option<u32>) -> Result<()> {
    let existed = match fs::symlink_metadata(path) {
        Ok(m) if m.file_type().is_symlink() => bail!(
            "{}: a symbolic link; sds never writes through a link at a name it chose \
             (remove the link, or choose another folder)",
            path.display()
        ),
        Ok(m) if !m.is_file() => bail!(
            "{}: {}, not a regular file; sds writes only regular files",
            path.display(),
            describe(m.file_type())
        ),
        Ok(m) => {
            refuse_input(path, &m, inputs)?;
            true
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => false,
        Err(e) => return Err(e).with_context(|| format!("cannot inspect {}", path.display())),
    };
    let dir = path
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let tmp = scratch_name(dir, "tmp");
    let result = (|| -> Result<()> {
        let mut f = {
            let mut pending = pending();
            pending.temps.push(tmp.clone());
            // `create_new` (O_EXCL) never follows a link at the temporary name either.
            OpenOptions::new()
                .write(true)
                .create_new(true)
                .mode(0o666)
                .open(&tmp)
                .with_context(|| format!("cannot create {}", tmp.display()))?
        };
        if let Some(mode) = keep_mode {
            f.set_permissions(fs::Permissions::from_mode(mode))?;
        }
        f.write_all(bytes)?;
        f.sync_all()?;
        drop(f);
        let mut pending = pending();
        if existed {
            // The file replaced, kept under a second name (same folder, same file system);
            // moved aside when it cannot be linked (it is put back all the same).
            let backup = scratch_name(dir, "bak");
            fs::hard_link(path, &backup)
                .or_else(|_| fs::rename(path, &backup))
                .with_context(|| format!("cannot keep a copy of {}", path.display()))?;
            pending.replaced.push((path.to_path_buf(), backup));
        }
        // Checked again just before the rename: a folder, device or FIFO that appeared at the
        // name since is refused (a link there is replaced by the rename, never followed).
        if let Ok(m) = fs::symlink_metadata(path) {
            if !m.is_file() && !m.file_type().is_symlink() {
                bail!(
                    "{}: became {} while it was written; not replaced",
                    path.display(),
                    describe(m.file_type())
                );
            }
        }
        fs::rename(&tmp, path)?;
        pending.temps.retain(|t| t != &tmp);
        if !existed {
            pending.created.push(path.to_path_buf());
        }
        Ok(())
    })();
    result.with_context(|| format!("cannot write {}", path.display()))?;
    if let Some(n) = std::env::var(PLACE_HOLD_ENV)
        .ok()
        .and_then(|v| v.parse::<usize>().ok())
    {
        static PLACED: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
        if PLACED.fetch_add(1, Ordering::SeqCst) + 1 >= n {
            hold_until_signalled();
        }
    }
    Ok(())
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
pub fn refuse_clash(out: &Path, paths: &[PathBuf], what: &'static str) -> Result<(), OutputClash> {
    refuse_named_clash(out, "-o", paths, what)
}

/// [`refuse_clash`] for the output of another option than `-o`.
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

/// An output path that cannot be written, found before any work (`--rerun-list` in a folder
/// that does not exist, or naming a folder or device).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct BadOutputPath(pub String);

/// Checks, before any work, that `path` can be written as a file the user named: its folder
/// exists and is a folder, and the path is not a folder, device or FIFO.
pub fn check_folder(path: &Path) -> Result<(), BadOutputPath> {
    let dir = path
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
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

/// Writes `bytes` at `path`, a file the user named besides `-o` (the rerun list, the rerun
/// route XML), inside the run's output unit: refused as `-o` is (not a regular file, one of
/// the inputs, a dangling link), a link written through to its file as `-o` does, the file
/// replaced kept until [`commit`] and put back by [`roll_back`], as [`place`] does.
pub fn place_named(path: &Path, bytes: &[u8], inputs: &[PathBuf]) -> Result<()> {
    let (target, keep_mode) = check_target(path, inputs)?;
    place_mode(&target, bytes, inputs, keep_mode).with_context(|| {
        format!(
            "no report written (fix {}, or leave its option out)",
            path.display()
        )
    })
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

/// Refuses a path whose file (`meta`) is one of `inputs` (compared by device and inode).
fn refuse_input(path: &Path, meta: &fs::Metadata, inputs: &[PathBuf]) -> Result<()> {
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
    Ok(())
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
    refuse_input(path, &meta, inputs)?;
    let target =
        fs::canonicalize(path).with_context(|| format!("cannot resolve {}", path.display()))?;
    Ok((target, Some(meta.permissions().mode() & 0o7777)))
}

/// Writes `bytes` to `path` atomically (a temporary file in the same folder, then a rename), or
/// to standard output. `inputs` are the run's input files: `path` must not be one of them.
pub fn write_output(path: Option<&Path>, bytes: &[u8], inputs: &[PathBuf]) -> Result<()> {
    write_output_with(path, inputs, &|w| w.write_all(bytes))
}

/// [`write_output`] of what `write` writes, streamed through a buffer: a large report (a
/// 10,000-route run's JSON) is never held whole beside the report it renders.
pub fn write_output_with(
    path: Option<&Path>,
    inputs: &[PathBuf],
    write: &dyn Fn(&mut dyn Write) -> std::io::Result<()>,
) -> Result<()> {
    let Some(path) = path else {
        return write_stdout(write);
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
    let result = write_temp_then_rename(&tmp, &target, write, keep_mode);
    if result.is_err() {
        let mut pending = pending();
        let _ = fs::remove_file(&tmp);
        pending.temps.retain(|t| t != &tmp);
    }
    result.with_context(|| format!("cannot write {}", path.display()))
}

/// Creation and rename happen under the [`PENDING`] lock, so the signal thread either removes a
/// finished temporary file or stops the process before one exists: none is left behind.
fn write_temp_then_rename(
    tmp: &Path,
    target: &Path,
    write: &dyn Fn(&mut dyn Write) -> std::io::Result<()>,
    keep_mode: Option<u32>,
) -> Result<()> {
    let mut f = {
        let mut pending = pending();
        pending.temps.push(tmp.to_path_buf());
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
    let mut buffered = std::io::BufWriter::new(&mut f);
    write(&mut buffered)?;
    buffered.flush()?;
    drop(buffered);
    f.sync_all()?;
    drop(f);
    if let Some(ms) = std::env::var(DELAY_ENV).ok().and_then(|v| v.parse().ok()) {
        std::thread::sleep(std::time::Duration::from_millis(ms));
    }
    if std::env::var_os(HOLD_ENV).is_some() {
        hold_until_signalled();
    }
    let mut pending = pending();
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
    pending.temps.retain(|t| t != tmp);
    Ok(())
}

/// Standard output, refusing a closed one (Rust's standard library would swallow the EBADF).
fn write_stdout(write: &dyn Fn(&mut dyn Write) -> std::io::Result<()>) -> Result<()> {
    if STDOUT_CLOSED.load(std::sync::atomic::Ordering::Relaxed) {
        bail!("standard output is closed: the report cannot be written (use -o FILE)");
    }
    let mut out = std::io::BufWriter::new(std::io::stdout().lock());
    write(&mut out)
        .and_then(|()| out.flush())
        .context("cannot write the report to standard output")
}
