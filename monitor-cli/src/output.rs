//! Writing a rendering: to standard output, or atomically to a regular file, through the
//! library's write rules ([`monitor_host::write`], `docs/RELIABILITY.md`, "Output": atomic
//! writes, links and inputs refused, a file set all or nothing). This file keeps the process's
//! concerns: the one [`FileSet`] of the process, undone by the SIGINT / SIGTERM thread
//! ([`install_signal_cleanup`]); a closed standard output (an error, never a silently lost
//! report); the options' names in the messages; the test seams.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};

use anyhow::{bail, Context, Result};
use monitor_host::write::{FileSet, Hooks};

pub use monitor_host::write::{
    check_folder, refuse_clash, refuse_named_clash, BadOutputPath, OutputClash,
};

/// What this process has put on disk and not yet committed (the library's [`FileSet`]): the
/// signal thread and every error undo exactly this, nothing else ([`roll_back`]).
static PENDING: FileSet = FileSet::with_hooks(Hooks {
    before_rename: Some(final_write_seam),
    after_place: Some(place_seam),
});

/// Undoes every file written since the last [`commit`] (traces and figures: all or nothing).
pub fn roll_back() {
    PENDING.roll_back();
}

/// Keeps every file written since the last [`commit`] or [`roll_back`].
pub fn commit() {
    PENDING.commit();
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

/// The final write's seams: between writing the temporary file and renaming it.
fn final_write_seam() {
    if let Some(ms) = std::env::var(DELAY_ENV).ok().and_then(|v| v.parse().ok()) {
        std::thread::sleep(std::time::Duration::from_millis(ms));
    }
    if std::env::var_os(HOLD_ENV).is_some() {
        hold_until_signalled();
    }
}

/// The traces' seam: after placing [`PLACE_HOLD_ENV`] files.
fn place_seam() {
    if let Some(n) = std::env::var(PLACE_HOLD_ENV)
        .ok()
        .and_then(|v| v.parse::<usize>().ok())
    {
        static PLACED: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
        if PLACED.fetch_add(1, Ordering::SeqCst) + 1 >= n {
            hold_until_signalled();
        }
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
            // Die of the signal while holding the set's lock: the writer cannot start a new
            // file.
            PENDING.roll_back_then(|| {
                let _ = signal_hook::low_level::emulate_default_handler(sig);
                std::process::exit(128 + sig)
            });
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

/// Creates `dir` (recorded, for [`roll_back`]) and places each file
/// ([`FileSet::place_all`]).
fn place_all(dir: &Path, files: &[(PathBuf, Vec<u8>)], inputs: &[PathBuf]) -> Result<()> {
    Ok(PENDING.place_all(dir, files, inputs)?)
}

/// The names `--figures DIR` may write (to refuse an `-o` among them).
pub use monitor_host::report::render::FIGURE_NAMES;

/// Writes the run's pictures into `dir` (created if needed) and returns the names written,
/// leaving them to the caller's [`commit`] or [`roll_back`], as [`place_traces`].
pub fn place_figures(
    dir: &Path,
    report: &monitor_host::report::Report,
    inputs: &[PathBuf],
) -> Result<Vec<&'static str>> {
    let named = monitor_host::report::render::figures(report);
    let names = named.iter().map(|(n, _)| *n).collect();
    let files: Vec<(PathBuf, Vec<u8>)> = named
        .into_iter()
        .map(|(n, svg)| (dir.join(n), svg.into_bytes()))
        .collect();
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

/// Writes `bytes` at `path`, a file the user named besides `-o` (the rerun list, the rerun
/// route XML), inside the run's output unit ([`FileSet::place_named`]).
pub fn place_named(path: &Path, bytes: &[u8], inputs: &[PathBuf]) -> Result<()> {
    Ok(PENDING.place_named(path, bytes, inputs)?)
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
    match path {
        None => write_stdout(write),
        Some(path) => Ok(PENDING.write_file(path, inputs, write)?),
    }
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
