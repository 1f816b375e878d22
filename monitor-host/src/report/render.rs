//! The report in one of its formats (docs/USAGE.md, `--format`): the one dispatch from a
//! [`Format`] to its rendering, which `sds score`, `sds merge`, `sds watch` and the Python
//! package's pages all call, so that a format means the same bytes in every front end.
//! The comparison's formats (`sds compare`, docs/SCORE.md §10.3) are [`render_compare`].

use std::io::{self, Write};
use std::path::PathBuf;

use crate::model::report::Report;
use crate::model::status::RoundStatus;
use crate::report::grid::Style;
use crate::report::table::{self, TableOptions};
use crate::report::{compare_table, csv, html, json, route_chart, waterfall};
use crate::stats::{Comparison, Model};

named_enum! {
    /// A format of the report (`--format`; every front end's spelling).
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    pub enum Format {
        /// The JSON report of docs/SCORE.md §13.
        Json = "json",
        /// The papers' tables as text.
        Table = "table",
        /// The same tables in Markdown.
        Markdown = "markdown",
        /// The same tables in LaTeX (booktabs).
        Latex = "latex",
        /// One line per route (with a breakdown: one line per group, then `combined`).
        Csv = "csv",
        /// One self-contained HTML page.
        Html = "html",
    }
}

impl Format {
    /// The style of a table format (`table`, `markdown`, `latex`), else `None`. The table
    /// formats break the run down by scenario when no other breakdown is asked for.
    ///
    /// ```
    /// use monitor_host::report::render::Format;
    /// assert!(Format::Markdown.style().is_some() && Format::Csv.style().is_none());
    /// ```
    pub fn style(self) -> Option<Style> {
        match self {
            Format::Table => Some(Style::Text),
            Format::Markdown => Some(Style::Markdown),
            Format::Latex => Some(Style::Latex),
            Format::Json | Format::Csv | Format::Html => None,
        }
    }

    /// What the format writes, as `--help` says it.
    pub fn help(self) -> &'static str {
        match self {
            Format::Json => "The JSON report of docs/SCORE.md §13",
            Format::Table => {
                "The papers' tables as text: Bench2Drive's main table, Safe2Drive Table 1, \
                 Table 2-style breakdown, and with `--group-by weather` the Table 3-style \
                 infraction table"
            }
            Format::Markdown => "The same tables in Markdown",
            Format::Latex => "The same tables in LaTeX (booktabs)",
            Format::Csv => {
                "One line per route (with `--group-by`: one line per group, then `combined`)"
            }
            Format::Html => {
                "One self-contained HTML page: the tables, a sortable route table, per route \
                 its collision figures and chunk timelines, the warnings (`sds compare`: runs \
                 side by side)"
            }
        }
    }
}

/// What a rendering needs besides the report.
#[derive(Clone, Debug, Default)]
pub struct RenderOptions<'a> {
    /// The tables' options (the extra infraction lists).
    pub tables: TableOptions,
    /// The run's name in the HTML page's title ([`run_name`]).
    pub name: String,
    /// A live round of a watch: the HTML page reloads itself every so many seconds and says
    /// that it is live ([`html::live_page`]); never in a final report.
    pub live: Option<(f64, &'a RoundStatus)>,
}

/// The run's name in the HTML page: the inputs' file (or folder) names, never their paths (a
/// page is shared; an absolute path tells where the files sat).
///
/// ```
/// use monitor_host::report::render::run_name;
/// use std::path::PathBuf;
/// assert_eq!(run_name(&[PathBuf::from("/runs/a.json"), PathBuf::from("b")]), "a.json, b");
/// ```
pub fn run_name(paths: &[PathBuf]) -> String {
    paths
        .iter()
        .map(|p| {
            p.file_name().map_or_else(
                || p.display().to_string(),
                |n| n.to_string_lossy().into_owned(),
            )
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// The report in `format`, written to `out` as it is rendered: JSON streams (a large run's
/// text is never held whole beside its report); the other formats are rendered, then written.
///
/// # Errors
/// What `out` returns.
pub fn write(
    report: &Report,
    format: Format,
    options: &RenderOptions<'_>,
    out: &mut dyn Write,
) -> io::Result<()> {
    let tables =
        |style| table::render(&table::report_tables(report, &options.tables), style).into_bytes();
    let bytes = match format {
        Format::Json => return json::write(report, out),
        Format::Csv => csv::groups_csv(report).unwrap_or_else(|| csv::csv(report)),
        Format::Table => tables(Style::Text),
        Format::Markdown => tables(Style::Markdown),
        Format::Latex => tables(Style::Latex),
        Format::Html => {
            let page = html::page(report, &options.tables, &options.name);
            match options.live {
                Some((refresh, status)) => html::live_page(&page, status, refresh),
                None => page,
            }
            .into_bytes()
        }
    };
    out.write_all(&bytes)
}

/// [`write()`] into bytes.
///
/// ```
/// use monitor_host::report::render::{render, Format, RenderOptions};
/// use monitor_host::{demo, score_run, Inputs, Settings};
/// let dir = tempfile::tempdir()?;
/// let run = demo::write(dir.path())?;
/// let report = score_run(&Inputs::new([run.results]), &Settings::default())?;
/// let options = RenderOptions { name: "demo".into(), ..RenderOptions::default() };
/// let csv = render(&report, Format::Csv, &options)?;
/// assert!(csv.starts_with(b"route_id,"));
/// let page = render(&report, Format::Html, &options)?;
/// assert!(String::from_utf8(page)?.contains("<title>"));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// Only if the JSON serialisation fails, which the report's types rule out.
pub fn render(report: &Report, format: Format, options: &RenderOptions<'_>) -> io::Result<Vec<u8>> {
    if format == Format::Json {
        // Measured first, so the buffer is allocated once at its size.
        return Ok(json::json(report)?);
    }
    let mut out = Vec::new();
    write(report, format, options, &mut out)?;
    Ok(out)
}

/// The names of the run's figures (`--figures DIR`, the pictures `sds.log` logs).
pub const FIGURE_NAMES: [&str; 2] = ["decomposition.svg", "routes.svg"];

/// The run's figures by file name: `decomposition.svg` (the waterfall from DS to SDS; left out
/// when the run has no decomposition) and `routes.svg` (DS and DS_safe per route).
pub fn figures(report: &Report) -> Vec<(&'static str, String)> {
    let decomposition = report.summary.scores.decomposition.as_ref();
    [
        (FIGURE_NAMES[0], decomposition.map(waterfall::svg)),
        (FIGURE_NAMES[1], Some(route_chart::svg(&report.routes))),
    ]
    .into_iter()
    .filter_map(|(name, svg)| svg.map(|s| (name, s)))
    .collect()
}

/// The formats of a comparison (`sds compare`): every format but `csv`.
pub const COMPARE_FORMATS: [Format; 5] = [
    Format::Json,
    Format::Table,
    Format::Markdown,
    Format::Latex,
    Format::Html,
];

/// A comparison that cannot be rendered.
#[derive(Debug, thiserror::Error)]
pub enum CompareFormatError {
    /// A format a comparison has not ([`COMPARE_FORMATS`]).
    #[error("sds compare writes {}, not {}", crate::named::choices(&COMPARE_FORMATS.map(Format::name)), .0.name())]
    Unsupported(Format),
    /// The JSON serialisation failed (the comparison's types rule it out).
    #[error(transparent)]
    Json(#[from] serde_json::Error),
}

/// The comparison `c` of `models` in `format`: the `sds-compare/1` report, its tables or its
/// page.
///
/// # Errors
/// [`CompareFormatError::Unsupported`] for `csv`.
pub fn render_compare(
    c: &Comparison,
    models: &[Model],
    format: Format,
) -> Result<Vec<u8>, CompareFormatError> {
    Ok(match (format, format.style()) {
        (Format::Json, _) => {
            let mut v = serde_json::to_vec_pretty(c)?;
            v.push(b'\n');
            v
        }
        (Format::Html, _) => html::compare_page(c, models).into_bytes(),
        (_, Some(style)) => table::render(&compare_table::compare_tables(c), style).into_bytes(),
        (_, None) => return Err(CompareFormatError::Unsupported(format)),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every format renders the demo run as its own module does, and `write` streams the same
    /// bytes as `render` returns.
    #[test]
    fn every_format_is_its_renderer() {
        let dir = tempfile::tempdir().unwrap();
        let run = crate::demo::write(dir.path()).unwrap();
        let inputs = crate::Inputs {
            telemetry: Some(run.telemetry),
            ..crate::Inputs::new([run.results])
        };
        let report = crate::score_run(&inputs, &crate::Settings::default()).unwrap();
        let options = RenderOptions {
            name: "demo".into(),
            ..RenderOptions::default()
        };
        for &format in Format::ALL {
            let bytes = render(&report, format, &options).unwrap();
            let mut streamed = Vec::new();
            write(&report, format, &options, &mut streamed).unwrap();
            assert_eq!(bytes, streamed, "{}", format.name());
            let direct = match format {
                Format::Json => json::json(&report).unwrap(),
                Format::Csv => csv::csv(&report),
                Format::Html => html::page(&report, &options.tables, "demo").into_bytes(),
                _ => table::render(
                    &table::report_tables(&report, &options.tables),
                    format.style().unwrap(),
                )
                .into_bytes(),
            };
            assert_eq!(bytes, direct, "{}", format.name());
        }
    }

    /// A comparison has every format but CSV, and says so with the names.
    #[test]
    fn a_comparison_refuses_csv_by_name() {
        let e = CompareFormatError::Unsupported(Format::Csv);
        assert_eq!(
            e.to_string(),
            "sds compare writes json, table, markdown, latex or html, not csv"
        );
    }
}
