//! The status of one round of a watch (docs/USAGE.md §8): the one schema of `sds watch
//! --status-json`'s lines and of `sds.watch`'s `status` dict, made by
//! [`crate::app::watch::watcher::Watcher`] and rendered by [`crate::report::status`].

/// The longest `interval` between rounds: one day, s.
pub const MAX_INTERVAL: f64 = 86_400.0;
/// The longest `timeout`: 365 days, s.
pub const MAX_TIMEOUT: f64 = 31_536_000.0;

/// One round's status (docs/USAGE.md §8): the same fields for every round, `sds watch --status-json`'s
/// line and `sds.watch`'s `status` dict alike. A retried round keeps the figures of the last good
/// reading and adds `retry`.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct RoundStatus {
    /// The round's number, from 1 (retried rounds count).
    pub round: usize,
    /// When the round ran, UTC (`2026-11-27T17:45:33Z`).
    pub time: String,
    /// Routes with a record.
    pub done: usize,
    /// The benchmark's size N.
    pub n: usize,
    /// DS over the routes done.
    pub ds_done: Option<f64>,
    /// DS over N, the routes not done counting 0.
    pub ds_n: Option<f64>,
    /// SDS over the routes done.
    pub sds_done: Option<f64>,
    /// SDS over N.
    pub sds_n: Option<f64>,
    /// The last route: the last replayed in report order, else the last with a record.
    pub last_route: Option<String>,
    /// Its state (`scored`, `invalid: ...`).
    pub last_state: Option<String>,
    /// Its DS.
    pub last_ds: Option<f64>,
    /// Routes whose record says the run broke: the rerun list's classes but `missing` and
    /// `timeout` ([`crate::report::rerun_list::crashes`]; a `Failed - TickRuntime` route is the
    /// agent's outcome, not a crash).
    pub crashes: usize,
    /// Estimated seconds left (`crate::app::watch::watcher::WatchStatus::seconds_left`).
    pub seconds_left: Option<f64>,
    /// Routes replayed this round.
    pub rescored: usize,
    /// Routes taken from the cache this round.
    pub reused: usize,
    /// The ids of the routes replayed, sorted.
    pub rescored_routes: Vec<String>,
    /// Something changed since the previous scored round.
    pub changed: bool,
    /// The route set is complete (`crate::app::watch::watcher::WatchStatus::complete`).
    pub complete: bool,
    /// Rounds retried (a results file caught half-written) since the previous good reading; a
    /// retried round counts itself.
    pub retries: usize,
    /// The round's time, ms.
    pub round_ms: f64,
    /// Why the watch stopped (`complete`, `once`, `timeout`, `interrupted`), on the last line.
    pub stopped: Option<String>,
    /// A retried round only: why, naming the file.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub retry: Option<String>,
    /// Shard checkpoints with no new record for longer than K times their median route time
    /// ([`crate::model::shard_stall`], docs/SCORE.md §13.2); empty when none is.
    pub stalled: Vec<crate::model::shard_stall::Stalled>,
}
