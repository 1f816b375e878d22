//! Text from the inputs, made safe for its reader: the one place where strings read from files
//! (route ids, statuses, scenario names, labels, paths, parser messages) are escaped before they
//! reach a terminal, a table, a page or a spreadsheet.
//!
//! - [`printable`] (every rendering: stderr, the text, Markdown and LaTeX tables, the HTML page
//!   and the trace SVG, CSV): every character for which [`is_hidden`] holds is written as a
//!   Rust escape (`\u{1b}`, `\r`, `\n`, `\t`, `\u{202e}`): control characters (C0 such as ESC,
//!   CR, LF, TAB; DEL; C1), so an id holding an escape sequence cannot erase or rewrite the line
//!   it is printed on, and the bidirectional and invisible format characters (U+061C,
//!   U+200B-U+200F, U+2028-U+202E, U+2066-U+2069, U+FEFF), so a route id cannot be made to read
//!   as another (`RouteScenario_1\u{202e}01` shown as `RouteScenario_110`). Everything else,
//!   non-ASCII letters included, is kept.
//! - [`csv_cell`] (CSV): [`printable`], then a cell that starts with `=`, `+`, `-`, `@`, TAB or
//!   CR is prefixed with `'`, so a spreadsheet shows it as text instead of running it as a
//!   formula (formula injection from a submitted results file or label file). Every string
//!   cell of every CSV rendering (per route, per group) goes through it: numbers are written as
//!   numbers (a negative number stays a number). Quoting of `"`, `,`, CR and LF is the `csv`
//!   crate's.
//! - [`markdown`] (Markdown tables: every cell and the title, after [`printable`]) and
//!   [`markdown_paragraph`] (the notes under a table): the text renders as itself in CommonMark
//!   and on GitHub, never as markup. A backslash goes before `\\`, `` ` ``, `*`, `[`, `]`, `<`,
//!   `>`, `!`, `|`, `~`, `$` and `&` (no emphasis, code, link, image, raw HTML, `<...>` autolink,
//!   strikethrough, math or entity can start), before `_` unless it stands inside a word
//!   (`RouteScenario_1_rep0` stays: there it cannot make emphasis), before `.` unless it stands
//!   between two digits (`1.50` stays, `www.` and `evil.example` are broken, so no `www.` autolink), and
//!   before `:` when `/` follows (no `https://` autolink). `(` and `)` stay: they make a link
//!   only after `]`, which is always escaped. A paragraph also escapes a block marker at its
//!   start (`#`, `>`, `-`, `+`, `=`, `1.` / `1)`). What escaping cannot stop: GitHub still links
//!   an address shaped like `name@host.tld` as `mailto:` (its text is the address itself) and
//!   its own `@user` and `#123` references, which it finds in the rendered text.
//!
//! ```
//! use monitor_host::report::escape::{csv_cell, printable};
//! assert_eq!(printable("Route\u{1b}[2K\r_1"), "Route\\u{1b}[2K\\r_1");
//! assert_eq!(printable("Straße"), "Straße");
//! assert_eq!(csv_cell("=HYPERLINK(\"x\")"), "'=HYPERLINK(\"x\")");
//! assert_eq!(csv_cell("RouteScenario_1_rep0"), "RouteScenario_1_rep0");
//! ```

use std::borrow::Cow;

/// Whether `c` must not reach a reader raw: a control character, or a bidirectional or
/// invisible format character (see the module docs).
///
/// ```
/// use monitor_host::report::escape::is_hidden;
/// assert!(is_hidden('\u{202e}') && is_hidden('\u{200b}') && is_hidden('\u{feff}') && is_hidden('\u{1b}'));
/// assert!(!is_hidden('ß') && !is_hidden(' '));
/// ```
pub fn is_hidden(c: char) -> bool {
    c.is_control()
        || matches!(
            c,
            '\u{061c}'
                | '\u{200b}'..='\u{200f}'
                | '\u{2028}'..='\u{202e}'
                | '\u{2066}'..='\u{2069}'
                | '\u{feff}'
        )
}

/// `s` with every control, bidirectional and invisible format character escaped (see the
/// module docs).
///
/// ```
/// use monitor_host::report::escape::printable;
/// assert_eq!(printable("Route_1\u{202e}01"), "Route_1\\u{202e}01");
/// ```
pub fn printable(s: &str) -> Cow<'_, str> {
    if !s.chars().any(is_hidden) {
        return Cow::Borrowed(s);
    }
    let mut out = String::with_capacity(s.len() + 8);
    for c in s.chars() {
        if is_hidden(c) {
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

/// Whether `c` at `i` in `chars` must be backslash-escaped in Markdown (see the module docs).
fn markdown_escapes(chars: &[char], i: usize) -> bool {
    let at = |j: Option<usize>| j.and_then(|j| chars.get(j)).copied();
    let digit = |j| at(j).is_some_and(|c| c.is_ascii_digit());
    let alnum = |j| at(j).is_some_and(char::is_alphanumeric);
    match chars[i] {
        '\\' | '`' | '*' | '[' | ']' | '<' | '>' | '!' | '|' | '~' | '$' | '&' => true,
        '.' => !(digit(i.checked_sub(1)) && digit(Some(i + 1))),
        // Inside a word `_` can neither open nor close emphasis (`RouteScenario_1_rep0` stays).
        '_' => !(alnum(i.checked_sub(1)) && alnum(Some(i + 1))),
        ':' => chars.get(i + 1) == Some(&'/'),
        _ => false,
    }
}

/// Text for a Markdown table cell that renders as itself: no markup, link, image or HTML can
/// start in it (see the module docs). Apply it after [`printable`].
///
/// ```
/// use monitor_host::report::escape::markdown;
/// assert_eq!(markdown("<script>x</script>"), "\\<script\\>x\\</script\\>");
/// assert_eq!(markdown("[log](https://evil.example)"), "\\[log\\](https\\://evil\\.example)");
/// assert_eq!(markdown("1.50 ± 0.25"), "1.50 ± 0.25");
/// ```
pub fn markdown(s: &str) -> String {
    let chars: Vec<char> = s.chars().collect();
    let mut out = String::with_capacity(s.len() + 8);
    for (i, &c) in chars.iter().enumerate() {
        if markdown_escapes(&chars, i) {
            out.push('\\');
        }
        out.push(c);
    }
    out
}

/// [`markdown`] for a paragraph (a note under a table): also escapes a block marker at its
/// start, so the line cannot become a heading, quote, list or rule.
///
/// ```
/// use monitor_host::report::escape::markdown_paragraph;
/// assert_eq!(markdown_paragraph("# big"), "\\# big");
/// assert_eq!(markdown_paragraph("12) item"), "12\\) item");
/// assert_eq!(markdown_paragraph("a - b"), "a - b");
/// ```
pub fn markdown_paragraph(s: &str) -> String {
    let body = markdown(s);
    if body.starts_with(['#', '>', '-', '+', '=']) {
        return format!("\\{body}");
    }
    // An ordered list marker: digits, then `)` (a `.` there is escaped by `markdown`).
    let digits = body.chars().take_while(char::is_ascii_digit).count();
    if digits > 0 && body[digits..].starts_with(')') {
        return format!("{}\\{}", &body[..digits], &body[digits..]);
    }
    body
}

/// A string cell of a CSV rendering: [`printable`], and neutralised against formula injection
/// (see the module docs).
///
/// ```
/// use monitor_host::report::escape::csv_cell;
/// assert_eq!(csv_cell("-2+3+cmd|' /C calc'!A0"), "'-2+3+cmd|' /C calc'!A0");
/// assert_eq!(csv_cell("\tx"), "'\\tx");
/// assert_eq!(csv_cell("a\u{1b}b"), "a\\u{1b}b");
/// ```
pub fn csv_cell(s: &str) -> Cow<'_, str> {
    if s.starts_with(['=', '+', '-', '@', '\t', '\r']) {
        Cow::Owned(format!("'{}", printable(s)))
    } else {
        printable(s)
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
        for c in [
            '\u{061c}', '\u{200b}', '\u{200e}', '\u{200f}', '\u{202a}', '\u{202e}', '\u{2066}',
            '\u{2069}', '\u{feff}',
        ] {
            let s = format!("a{c}b");
            assert_eq!(printable(&s), format!("a\\u{{{:x}}}b", c as u32));
            assert_eq!(csv_cell(&s), printable(&s));
        }
    }

    #[test]
    fn markdown_escapes_markup_and_keeps_numbers() {
        assert_eq!(markdown("a\\|b"), "a\\\\\\|b");
        assert_eq!(markdown("www.x"), "www\\.x");
        assert_eq!(markdown("_a_b_ é_1"), "\\_a_b\\_ é_1");
        assert_eq!(markdown("-0.25 & 3.5."), "-0.25 \\& 3.5\\.");
        assert_eq!(markdown("a:b"), "a:b");
        assert_eq!(markdown_paragraph("1. x"), "1\\. x");
        assert_eq!(markdown_paragraph(""), "");
    }
}
