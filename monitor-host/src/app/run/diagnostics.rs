//! The run's notes, raised once for every front end (issue 48): facts about a scored run that
//! ask nothing of the user but that a reader should know, added to the report's warnings
//! ([`Warning::is_note`]) so that the `sds` command prints them and Python warns them alike.

use crate::input::warning::Warning;
use crate::model::report::Report;
use crate::pipeline::step_period::DtSource;
use crate::route::trace::TRACES_PER_ROUTE;

/// Adds the run's notes to its warnings: [`period_notes`], then [`untraced_note`].
pub fn add_notes(report: &mut Report) {
    let mut notes = period_notes(report);
    notes.extend(untraced_note(report));
    report.warnings.extend(notes);
}

/// One note per inferred step period other than CARLA's 0.05 s tick, naming its routes, in
/// increasing period: a period read wrong would scale every speed and time of a route.
pub fn period_notes(report: &Report) -> Vec<Warning> {
    let mut by_dt: Vec<(f64, Vec<String>)> = Vec::new();
    for r in &report.routes {
        let (Some(dt), Some(DtSource::Inferred), Some(id)) =
            (r.dt, r.dt_source, r.route_id.as_deref())
        else {
            continue;
        };
        if dt == crate::pipeline::step_period::TICK {
            continue;
        }
        match by_dt.iter_mut().find(|(d, _)| *d == dt) {
            Some((_, ids)) => ids.push(id.to_string()),
            None => by_dt.push((dt, vec![id.to_string()])),
        }
    }
    by_dt.sort_by(|a, b| a.0.total_cmp(&b.0));
    by_dt
        .into_iter()
        .map(|(dt, routes)| Warning::PeriodInferred { dt, routes })
        .collect()
}

/// The aligned collisions left without a trace past the first [`TRACES_PER_ROUTE`] of their
/// route, if any.
pub fn untraced_note(report: &Report) -> Option<Warning> {
    let collisions: usize = report
        .routes
        .iter()
        .filter(|r| r.traces.len() >= TRACES_PER_ROUTE)
        .map(|r| {
            let aligned = r.collision_events.iter().filter(|e| e.frame.is_some());
            aligned.count().saturating_sub(r.traces.len())
        })
        .sum();
    (collisions > 0).then_some(Warning::Untraced {
        collisions,
        cap: TRACES_PER_ROUTE,
    })
}

#[cfg(test)]
mod tests {
    use crate::app::score::ScoreRequest;
    use crate::{demo, Inputs, NoProgress, Warning};

    /// Issue 48 item 2: the demo's 10 Hz route is noted in the report itself (once, as a note),
    /// for every front end, where only the command line printed it.
    #[test]
    fn i48_2_inferred_period_is_a_note_of_the_report() {
        let dir = tempfile::tempdir().unwrap();
        let run = demo::write(dir.path()).unwrap();
        let request = ScoreRequest::new(Inputs {
            telemetry: Some(run.telemetry),
            ..Inputs::new([run.results])
        });
        let report = request.score(&NoProgress).unwrap().report;
        let notes: Vec<&Warning> = report.warnings.iter().filter(|w| w.is_note()).collect();
        assert_eq!(notes.len(), 1, "{notes:?}");
        let Warning::PeriodInferred { dt, routes } = notes[0] else {
            panic!("{notes:?}")
        };
        assert_eq!(
            (*dt, routes.as_slice()),
            (0.1, &["RouteScenario_900008_rep0".to_string()][..])
        );
        assert!(notes[0]
            .to_string()
            .starts_with("step period inferred as 0.1 s"));
    }
}
