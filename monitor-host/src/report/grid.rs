//! A table as cells, and its three renderings: aligned text, Markdown, and LaTeX (`booktabs`).
//! The report's tables ([`crate::report::table`]) are built once as [`Grid`]s and rendered in
//! the format asked for, so the three always hold the same numbers.
//!
//! ```
//! use monitor_host::report::grid::{Grid, Style};
//! let mut g = Grid::new("Scores", ["model", "DS"]);
//! g.row(["a_b", "1.50"]);
//! g.total(["Combined", "1.50"]);
//! assert!(g.render(Style::Markdown).contains("| a_b | 1.50 |"));
//! let tex = g.render(Style::Latex);
//! assert!(tex.contains("\\toprule") && tex.contains("a\\_b & 1.50 \\\\") && tex.contains("\\midrule\nCombined"));
//! ```

/// The rendering of a [`Grid`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Style {
    /// Columns padded with spaces, the first left-aligned, the others right-aligned.
    Text,
    /// A GitHub-flavoured Markdown table.
    Markdown,
    /// A LaTeX `tabular` with `booktabs` rules.
    Latex,
}

/// A titled table: a header, rows, an optional total row below a rule, and notes under it.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Grid {
    /// The title (a caption).
    pub title: String,
    /// Column headings.
    pub header: Vec<String>,
    /// Body rows.
    pub rows: Vec<Vec<String>>,
    /// The total row (e.g. `Combined`), set off by a rule.
    pub total: Option<Vec<String>>,
    /// Lines printed under the table.
    pub notes: Vec<String>,
}

fn cells<I: IntoIterator<Item = S>, S: Into<String>>(c: I) -> Vec<String> {
    c.into_iter().map(Into::into).collect()
}

impl Grid {
    /// An empty table with this title and header.
    pub fn new<I: IntoIterator<Item = S>, S: Into<String>>(title: &str, header: I) -> Self {
        Grid {
            title: title.into(),
            header: cells(header),
            ..Grid::default()
        }
    }

    /// Appends a body row.
    pub fn row<I: IntoIterator<Item = S>, S: Into<String>>(&mut self, row: I) {
        self.rows.push(cells(row));
    }

    /// Sets the total row.
    pub fn total<I: IntoIterator<Item = S>, S: Into<String>>(&mut self, row: I) {
        self.total = Some(cells(row));
    }

    /// Adds a note under the table.
    pub fn note(&mut self, note: impl Into<String>) {
        self.notes.push(note.into());
    }

    /// The table in `style`, ending with a newline. Every cell, the title and the notes are
    /// escaped first ([`crate::report::escape::printable`]: labels, towns and run names come
    /// from the inputs); a cell may be of any length.
    pub fn render(&self, style: Style) -> String {
        let shown = self.printable();
        match style {
            Style::Text => shown.text(),
            Style::Markdown => shown.markdown(),
            Style::Latex => shown.latex(),
        }
    }

    /// The grid with every string escaped for display.
    fn printable(&self) -> Grid {
        let p = |s: &String| crate::report::escape::printable(s).into_owned();
        let row = |r: &Vec<String>| r.iter().map(p).collect();
        Grid {
            title: p(&self.title),
            header: row(&self.header),
            rows: self.rows.iter().map(row).collect(),
            total: self.total.as_ref().map(row),
            notes: self.notes.iter().map(p).collect(),
        }
    }

    fn all_rows(&self) -> impl Iterator<Item = &Vec<String>> {
        std::iter::once(&self.header)
            .chain(&self.rows)
            .chain(&self.total)
    }

    fn text(&self) -> String {
        let cols = self.header.len();
        let mut width = vec![0usize; cols];
        for r in self.all_rows() {
            for (w, c) in width.iter_mut().zip(r) {
                *w = (*w).max(c.chars().count());
            }
        }
        // Padded by hand: a `{c:<w$}` width is a u16, and a cell from the inputs (a scenario
        // name, a label) may be longer than 65,535 characters.
        let line = |r: &Vec<String>| {
            let mut s = String::new();
            for (i, (c, w)) in r.iter().zip(&width).enumerate() {
                let pad = " ".repeat(w.saturating_sub(c.chars().count()));
                if i == 0 {
                    s.push_str(c);
                    s.push_str(&pad);
                } else {
                    s.push_str("  ");
                    s.push_str(&pad);
                    s.push_str(c);
                }
            }
            s.trim_end().to_string() + "\n"
        };
        let rule = "-".repeat(width.iter().sum::<usize>() + 2 * cols.saturating_sub(1)) + "\n";
        let mut out = format!("{}\n", self.title);
        out += &line(&self.header);
        out += &rule;
        for r in &self.rows {
            out += &line(r);
        }
        if let Some(t) = &self.total {
            out += &rule;
            out += &line(t);
        }
        for n in &self.notes {
            out += &format!("  {n}\n");
        }
        out
    }

    fn markdown(&self) -> String {
        // Every cell, the title and the notes render as their text, never as markup: a name
        // from the inputs cannot become a link, an image or HTML (`escape::markdown`).
        let esc = |c: &String| crate::report::escape::markdown(c);
        let line = |r: &Vec<String>| {
            format!(
                "| {} |\n",
                r.iter().map(esc).collect::<Vec<_>>().join(" | ")
            )
        };
        let mut out = format!("**{}**\n\n", esc(&self.title));
        out += &line(&self.header);
        let align: Vec<&str> = (0..self.header.len())
            .map(|i| if i == 0 { ":--" } else { "--:" })
            .collect();
        out += &format!("| {} |\n", align.join(" | "));
        for r in &self.rows {
            out += &line(r);
        }
        if let Some(t) = &self.total {
            let bold: Vec<String> = t.iter().map(|c| format!("**{}**", esc(c))).collect();
            out += &format!("| {} |\n", bold.join(" | "));
        }
        for n in &self.notes {
            out += &format!("\n{}\n", crate::report::escape::markdown_paragraph(n));
        }
        out
    }

    fn latex(&self) -> String {
        let esc = |c: &String| {
            let mut s = String::new();
            for ch in c.chars() {
                match ch {
                    '_' | '%' | '&' | '#' | '$' | '{' | '}' => {
                        s.push('\\');
                        s.push(ch);
                    }
                    '±' => s.push_str("$\\pm$"),
                    '~' => s.push_str("\\textasciitilde{}"),
                    '^' => s.push_str("\\textasciicircum{}"),
                    '\\' => s.push_str("\\textbackslash{}"),
                    _ => s.push(ch),
                }
            }
            s
        };
        let line = |r: &Vec<String>| {
            format!(
                "{} \\\\\n",
                r.iter()
                    // An undefined cell: an en dash in LaTeX (a bare `-` prints a hyphen).
                    .map(|c| if c == "-" { "--".to_string() } else { esc(c) })
                    .collect::<Vec<_>>()
                    .join(" & ")
            )
        };
        let spec: String = (0..self.header.len())
            .map(|i| if i == 0 { 'l' } else { 'r' })
            .collect();
        let mut out = format!(
            "% {}\n% needs \\usepackage{{booktabs}}\n\\begin{{tabular}}{{{spec}}}\n\\toprule\n",
            esc(&self.title)
        );
        out += &line(&self.header);
        out += "\\midrule\n";
        for r in &self.rows {
            out += &line(r);
        }
        if let Some(t) = &self.total {
            out += "\\midrule\n";
            out += &line(t);
        }
        out += "\\bottomrule\n\\end{tabular}\n";
        for n in &self.notes {
            out += &format!("% {}\n", esc(n));
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_aligns_columns_and_sets_off_the_total() {
        let mut g = Grid::new("T", ["group", "n"]);
        g.row(["a", "1"]);
        g.row(["longer", "100"]);
        g.total(["all", "101"]);
        g.note("a note");
        assert_eq!(
            g.render(Style::Text),
            "T\ngroup     n\n-----------\na         1\nlonger  100\n-----------\nall     101\n  a note\n"
        );
    }

    #[test]
    fn markdown_and_latex_escape() {
        let mut g = Grid::new("50% & more", ["a|b", "c"]);
        g.row(["x_1", "1 ± 2"]);
        let md = g.render(Style::Markdown);
        assert!(
            md.contains("| a\\|b | c |\n| :-- | --: |\n| x_1 | 1 ± 2 |"),
            "{md}"
        );
        let tex = g.render(Style::Latex);
        assert!(tex.starts_with("% 50\\% \\& more\n"), "{tex}");
        assert!(tex.contains("\\begin{tabular}{lr}"));
        assert!(tex.contains("x\\_1 & 1 $\\pm$ 2 \\\\"), "{tex}");
        assert!(tex.ends_with("\\bottomrule\n\\end{tabular}\n"));
    }
}
