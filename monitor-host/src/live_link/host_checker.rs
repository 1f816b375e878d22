//! The checker on the host (`sds checker`): reads the doer's bytes on one stream and writes its
//! answers on another, on the host's monotonic clock. For tests without QEMU, and for a safety
//! core that runs Linux.

use std::io::{Read, Write};
use std::sync::mpsc::{self, RecvTimeoutError};
use std::time::{Duration, Instant};

use monitor_core::link::{Checker, LinkConfig, LinkConfigError};

/// Runs a checker until `input` ends: every byte read goes to [`Checker::receive`], the
/// timeout is polled at its deadline, and every answer is written to `output` and flushed.
///
/// # Errors
/// An invalid `link`, or writing the answers failed (the doer went away).
///
/// ```
/// use monitor_core::link::{self, LinkConfig, Message};
/// let mut buf = [0u8; link::MAX_ENCODED];
/// let n = link::encode(&Message::Start(monitor_core::Config::DEFAULT), 0, &mut buf);
/// let mut answers = Vec::new();
/// monitor_host::live_link::host_checker::run(std::io::Cursor::new(buf[..n].to_vec()),
///                                            &mut answers, LinkConfig::DEFAULT).unwrap();
/// assert!(!answers.is_empty()); // the status that answers the start
/// ```
pub fn run(
    input: impl Read + Send + 'static,
    mut output: impl Write,
    link: LinkConfig,
) -> Result<(), RunError> {
    let mut checker: Checker = Checker::new(link)?;
    let (tx, rx) = mpsc::channel::<Vec<u8>>();
    let mut input = input;
    std::thread::spawn(move || {
        let mut buf = [0u8; 4096];
        loop {
            match input.read(&mut buf) {
                Ok(0) | Err(_) => break,
                Ok(n) => {
                    if tx.send(buf[..n].to_vec()).is_err() {
                        break;
                    }
                }
            }
        }
    });
    let t0 = Instant::now();
    let now_us = || t0.elapsed().as_micros() as u64;
    let mut out = Vec::new();
    loop {
        let wait = checker
            .deadline()
            .map(|d| Duration::from_micros(d.saturating_sub(now_us())))
            .unwrap_or(Duration::from_secs(3600));
        match rx.recv_timeout(wait) {
            Ok(bytes) => {
                checker.receive(&bytes, now_us(), &mut |b: &[u8]| out.extend_from_slice(b));
            }
            Err(RecvTimeoutError::Timeout) => {}
            Err(RecvTimeoutError::Disconnected) => break,
        }
        checker.poll(now_us(), &mut |b: &[u8]| out.extend_from_slice(b));
        if !out.is_empty() {
            output.write_all(&out).map_err(RunError::Write)?;
            output.flush().map_err(RunError::Write)?;
            out.clear();
        }
    }
    Ok(())
}

/// Why the host checker stopped.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// The link settings.
    #[error(transparent)]
    Config(#[from] LinkConfigError),
    /// Writing the answers.
    #[error("writing the checker's answers: {0}")]
    Write(#[source] std::io::Error),
}
