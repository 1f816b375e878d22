//! Text from the inputs, made safe for its reader: the one place where strings read from files
//! (route ids, statuses, scenario names, paths, parser messages) are escaped before they reach a
//! terminal or a spreadsheet.
//!
//! - [`printable`] (terminal): every control character (C0 such as ESC, CR, LF, TAB; DEL; C1) is
//!   written as a Rust escape (`\u{1b}`, `\r`, `\n`, `\t`), so an id holding an escape sequence
//!   cannot erase or rewrite the line it is printed on. Everything else, non-ASCII letters
//!   included, is kept.
//! - [`csv_cell`] (CSV): a cell that starts with `=`, `+`, `-`, `@`, TAB or CR is prefixed with
//!   `'`, so a spreadsheet shows it as text instead of running it as a formula (formula
//!   injection from a submitted results file). Only string cells from the inputs go through it:
//!   numbers are written as numbers (a negative number stays a number). Quoting of `"`, `,`,
//!   CR and LF is the `csv` crate's.
//!
//! ```
//! use monitor_host::report::escape::{csv_cell, printable};
//! assert_eq!(printable("Route\u{1b}[2K\r_1"), "Route\\u{1b}[2K\\r_1");
//! assert_eq!(printable("Straße"), "Straße");
//! assert_eq!(csv_cell("=HYPERLINK(\"x\")"), "'=HYPERLINK(\"x\")");
//! assert_eq!(csv_cell("RouteScenario_1_rep0"), "RouteScenario_1_rep0");
//! ```

use std::borrow::Cow;

/// `s` with every control character escaped (see the module docs).
pub fn printable(s: &str) -> Cow<'_, str> {
    if !s.chars().any(char::is_control) {
        return Cow::Borrowed(s);
    }
    let mut out = String::with_capacity(s.len() + 8);
    for c in s.chars() {
        if c.is_control() {
            out.extend(c.escape_default());
        } else {
            out.push(c);
        }
    }
    Cow::Owned(out)
}

/// [`printable`] for a message of several lines: each line escaped, the line breaks kept (a
/// message the tool writes over several lines stays readable; CR, ESC and every other control
/// character are still escaped, so no line can be erased or rewritten).
///
/// ```
/// use monitor_host::report::escape::printable_lines;
/// assert_eq!(printable_lines("a\u{1b}[2K\nb\r"), "a\\u{1b}[2K\nb\\r");
/// ```
pub fn printable_lines(s: &str) -> String {
    s.split('\n').map(printable).collect::<Vec<_>>().join("\n")
}

/// A string cell of a CSV rendering, neutralised against formula injection (see the module
/// docs).
pub fn csv_cell(s: &str) -> Cow<'_, str> {
    if s.starts_with(['=', '+', '-', '@', '\t', '\r']) {
        Cow::Owned(format!("'{s}"))
    } else {
        Cow::Borrowed(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_control_character_is_escaped() {
        for c in (0u32..0x20).chain([0x7f]).chain(0x80..0xa0) {
            let c = char::from_u32(c).unwrap();
            let s = format!("a{c}b");
            let p = printable(&s);
            assert!(!p.chars().any(char::is_control), "{c:?} -> {p:?}");
        }
        for s in ["+1", "-x", "@SUM(A1)", "\tx", "\rx"] {
            assert!(csv_cell(s).starts_with('\''), "{s:?}");
        }
        assert_eq!(csv_cell(""), "");
    }
}
