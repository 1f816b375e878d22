//! The exit codes of `sds`: one match on the library's [`ErrorKind`] ([`code`]), plus the
//! command's own usage errors and outcomes. docs/USAGE.md lists them; the test below pins the
//! table.

use monitor_host::ErrorKind;

/// The report was written, but some route has a problem.
pub const ROUTE_PROBLEMS: i32 = 3;
/// A usage error (clap's own code too).
pub const USAGE: i32 = 2;
/// The inputs hold no record at all.
pub const EMPTY_RUN: i32 = 4;
/// `sds compare --fail-if-worse` found a model worse than the baseline.
pub const WORSE: i32 = 5;
/// No report: an input could not be read, or the output not written.
pub const FAILED: i32 = 1;

/// The exit code of an error of this kind: what the user should fix decides it (an option: 2;
/// an input or the system: 1; nothing to score: 4).
pub fn code(kind: ErrorKind) -> i32 {
    match kind {
        ErrorKind::Option
        | ErrorKind::NeedsLabels
        | ErrorKind::MissingFolder
        | ErrorKind::Refused => USAGE,
        ErrorKind::EmptyRun => EMPTY_RUN,
        // `Io`, `Input`, `Cancelled`, `Internal`, and a kind this command does not know yet
        // (`ErrorKind` is non-exhaustive): no report.
        _ => FAILED,
    }
}

/// The exit code of an error that stopped the command: a library error by its kind, the
/// command's own refusals (an unknown `--infraction`, an `-o` among the written files) 2,
/// anything else (an output that cannot be written) 1.
pub fn of(e: &anyhow::Error) -> i32 {
    if let Some(e) = e.downcast_ref::<monitor_host::Error>() {
        return code(e.kind());
    }
    if let Some(e) = e.downcast_ref::<monitor_host::merge::MergeError>() {
        return code(e.kind());
    }
    if let Some(e) = e.downcast_ref::<monitor_host::SettingsError>() {
        return code(e.kind());
    }
    if let Some(e) = e.downcast_ref::<monitor_host::RequestError>() {
        return code(e.kind());
    }
    if let Some(e) = e.downcast_ref::<monitor_host::RerunError>() {
        return code(e.kind());
    }
    if e.downcast_ref::<super::output::OutputClash>().is_some()
        || e.downcast_ref::<super::output::BadOutputPath>().is_some()
    {
        return USAGE;
    }
    FAILED
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The whole table: every kind's exit code (the Python exception classes are pinned against
    /// the same kinds in the Python package's tests).
    #[test]
    fn exit_code_of_every_kind() {
        let table: Vec<(&str, i32)> = ErrorKind::ALL
            .iter()
            .map(|k| (k.name(), code(*k)))
            .collect();
        assert_eq!(
            table,
            [
                ("io", 1),
                ("input", 1),
                ("option", 2),
                ("needs-labels", 2),
                ("missing-folder", 2),
                ("refused", 2),
                ("empty-run", 4),
                ("cancelled", 1),
                ("internal", 1),
            ]
        );
    }
}
