//! The protocol table (docs/SCORE.md §13): one row per asked scoring protocol — DS, RC,
//! IS, SR, and HM for `f2d` — in text, Markdown, LaTeX and HTML. `docs/PROTOCOLS.md` explains
//! every protocol.

use crate::model::report::Report;
use crate::report::grid::Grid;
use crate::route::protocol::aggregate::ProtocolScores;
use crate::route::protocol::Protocol;

fn num(x: Option<f64>, digits: usize) -> String {
    x.map_or_else(|| "-".to_string(), |v| format!("{v:.digits$}"))
}

/// The table of `scores` (a run's summary or a group's), titled `title`.
pub fn protocol_grid(title: &str, scores: &ProtocolScores) -> Grid {
    let mut g = Grid::new(title, ["protocol", "", "DS", "RC", "IS", "SR(%)", "HM"]);
    for (p, a) in &scores.0 {
        g.row([
            p.id().to_string(),
            p.title().to_string(),
            num(a.driving_score, 2),
            num(a.route_completion, 2),
            num(a.infraction_score, 3),
            num(a.success_rate, 2),
            if *p == Protocol::F2d {
                num(a.hm, 2)
            } else {
                "-".into()
            },
        ]);
    }
    g.note(
        "the recorded events of each route under each protocol's arithmetic, not a re-run \
         (docs/PROTOCOLS.md)",
    );
    g
}

/// The run's protocol table; `None` when no protocol was asked.
///
/// ```
/// use monitor_host::report::protocol_table::protocol_table;
/// use monitor_host::{demo, score_run, Inputs, Settings};
/// let dir = tempfile::tempdir()?;
/// let run = demo::write(dir.path())?;
/// let inputs = Inputs { telemetry: Some(run.telemetry), ..Inputs::new([run.results]) };
/// let mut settings = Settings::default();
/// assert!(protocol_table(&score_run(&inputs, &settings)?).is_none());
/// settings.set("protocols", "all")?;
/// let g = protocol_table(&score_run(&inputs, &settings)?).unwrap();
/// assert_eq!(g.rows.len(), 5);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn protocol_table(report: &Report) -> Option<Grid> {
    let scores = report.summary.protocols.as_ref()?;
    Some(protocol_grid(
        "Scoring protocols: DS, route completion, infraction score, success rate, harmonic mean",
        scores,
    ))
}
