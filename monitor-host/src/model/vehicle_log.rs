//! A report of vehicle logs (docs/SCORE.md §2.4): a log has no Leaderboard record, so every
//! figure that needs one is dropped, when the logs are scored and when their parts are merged.

use super::report::Report;

/// What the report says once about every vehicle-log run.
pub const NO_LEADERBOARD: &str = "vehicle logs have no Leaderboard record: the report holds no \
    driving score, success rate, DS_safe, SDS or protocols (docs/SCORE.md §2.4); comfort, lateral \
    excess, braking before events, distance and stationary share are scored as usual";

/// Drops every figure that needs a Leaderboard record (its placeholders stood in for one); the
/// merge of vehicle-log parts too.
pub(crate) fn without_leaderboard(report: &mut Report) {
    for r in &mut report.routes {
        r.status = None;
        r.success = false;
        r.score_route = None;
        r.score_penalty = None;
        r.score_composed = None;
        r.p_safe = None;
        r.ds_safe = None;
        r.decomposition = None;
        r.protocols = None;
        r.penalty_check = None;
        r.min_speed_grid = None;
        r.efficiency = None;
        r.ability = None;
    }
    let s = &mut report.summary;
    s.scores.driving_score = None;
    s.scores.success_rate = None;
    s.scores.mean_ds_safe = None;
    s.scores.sds = None;
    s.scores.decomposition = None;
    s.protocols = None;
    s.penalty_mismatches.clear();
    // A log's record is made, never invalid (a merge reads the rows' empty status as invalid).
    s.invalid_records = 0;
    if let Some(b) = &mut s.bench2drive {
        b.driving_score = None;
        b.success_rate = None;
        b.efficiency = None;
        b.ability = None;
    }
}
