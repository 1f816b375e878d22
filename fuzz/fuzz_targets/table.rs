//! The table renderer (`monitor_host::report::grid`) and the HTML escaping on arbitrary cells:
//! repeated ones (a leading digit repeats a cell, within 512 bytes per input; cells past the
//! 65,535 a format width holds are a regression test's, see below) and ones full of
//! bidirectional, invisible and control characters (seeded). Never a panic; no rendering lets
//! such a character through raw (issue 29): the text, Markdown and LaTeX tables hold none but
//! their own line breaks, the HTML escape none at all.
#![no_main]

use libfuzzer_sys::fuzz_target;
use monitor_host::report::escape::is_hidden;
use monitor_host::report::grid::{Grid, Style};

/// The bytes the repeats of one input may add.
const REPEAT_BUDGET: usize = 512;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    // Cells are separated by `|`; a cell starting with a digit d is repeated 2^(2d) times, within
    // 512 bytes of repeats per input. Every character costs ~1 µs under the fuzzer's
    // instrumentation: 64 cells of up to 200,000 characters took ~130 ms an input (77 inputs in
    // 10 s, issue 34). Cells past the 65,535 a format width holds are the regression test
    // `r2_03_a_table_cell_of_any_length_renders`'s (monitor-cli/tests/it/regression.rs).
    let mut budget = REPEAT_BUDGET;
    let mut cells: Vec<String> = Vec::new();
    for c in text.split('|').take(64) {
        let reps = match c.as_bytes().first() {
            Some(d @ b'0'..=b'9') if !c.is_empty() => 1usize << (2 * (d - b'0') as usize).min(16),
            _ => 1,
        };
        let reps = reps.min(budget / c.len().max(1)).max(1);
        budget = budget.saturating_sub(reps.saturating_sub(1) * c.len());
        cells.push(c.repeat(reps));
    }
    if cells.is_empty() {
        return;
    }
    let cols = (cells.len() % 5) + 1;
    let mut g = Grid::new(&cells[0], cells.iter().take(cols).cloned());
    for row in cells.chunks(cols).skip(1) {
        g.row(row.iter().cloned());
    }
    g.total(cells.iter().rev().take(cols).cloned());
    g.note(cells.last().cloned().unwrap_or_default());
    for style in [Style::Text, Style::Markdown, Style::Latex] {
        let out = g.render(style);
        assert!(
            !out.chars().any(|c| is_hidden(c) && c != '\n'),
            "{style:?}: a raw hidden character"
        );
    }
    for c in &cells {
        let e = monitor_host::report::html::escape(c);
        assert!(!e.chars().any(is_hidden) && !e.contains(['<', '>', '"']));
    }
});
