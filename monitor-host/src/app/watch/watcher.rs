//! Scoring an evaluation while it runs (docs/USAGE.md §8): the same run as `sds score`,
//! read again every round, each route replayed again only when something it was made from
//! changed (its record, its telemetry files or the folders where its missing telemetry was
//! looked for, the route XML, the maps). [`Watcher::round`] is one round; `sds watch` and
//! `sds.watch` call it in a loop, render each report and decide when to stop.
//!
//! An evaluator rewrites its checkpoint in place, not atomically (truncated, then written), so a
//! round may find a file half-written: a results file that ends early, that is shorter than on
//! the previous round, or that is not there yet makes the round a [`RoundOutcome::Retry`] (the
//! last good reading stays current), never an error. An error no later write of the evaluator
//! can mend (a mistyped `--routes` or label file, a null label, duplicate route ids, a results
//! file that is not JSON from its first bytes) is returned at once, as `sds score` would stop.

use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::{Duration, SystemTime};

use crate::aggregate::aggregates::Scores;
use crate::aggregate::groups::GroupBy;
use crate::app::run::scored::{score_labelled_cached, LabelFiles, Scored};
use crate::app::run::{Inputs, NoProgress, ReplayCache};
use crate::error::Error;
use crate::input::record::LoadedRecord;
use crate::input::results_file::{read_results, ResultsError};
use crate::pipeline::outcome::{RouteOutcome, RouteState};
use crate::settings::Settings;

pub use crate::model::status::{RoundStatus, MAX_INTERVAL, MAX_TIMEOUT};
pub use crate::report::status::duration_text;

/// A results file's `progress` `[done, total]`, and the stamp of the file it was read from.
/// (None: a merged file, complete by itself.)
type Progress = (Option<Stamp>, Option<(u64, u64)>);

/// What tells a changed file or folder (docs/USAGE.md §8): its size, modification and status-change
/// times, and its inode (a `chmod`, a rename over it or a copy keeping the times all change one
/// of them). `None` for a path that does not exist.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Stamp {
    len: u64,
    modified: Option<SystemTime>,
    status_changed: (i64, i64),
    inode: (u64, u64),
}

impl Stamp {
    fn of(path: &Path) -> Option<Stamp> {
        use std::os::unix::fs::MetadataExt;
        let m = std::fs::metadata(path).ok()?;
        Some(Stamp {
            len: m.len(),
            modified: m.modified().ok(),
            status_changed: (m.ctime(), m.ctime_nsec()),
            inode: (m.dev(), m.ino()),
        })
    }

    /// Old enough to be trusted unchanged: modified (and its status changed) at least `racy`
    /// before `now`, or at least `racy` after it: a time that far in the future (a clock set
    /// wrong, `touch -d`) is not a write under way, and a later write sets it to the writer's
    /// now, which differs (it kept `sds watch` from ever stopping). An absent path is settled
    /// (its absence is what is kept).
    fn settled(stamp: Option<&Stamp>, now: SystemTime, racy: Duration) -> bool {
        let Some(s) = stamp else {
            return true;
        };
        let changed = SystemTime::UNIX_EPOCH
            + Duration::new(
                s.status_changed.0.max(0) as u64,
                s.status_changed.1.clamp(0, 999_999_999) as u32,
            );
        [s.modified, Some(changed)].iter().all(|t| {
            t.is_some_and(|t| match now.duration_since(t) {
                Ok(age) => age >= racy,
                Err(ahead) => ahead.duration() >= racy,
            })
        })
    }
}

/// Stamps of `paths`.
fn stamps(paths: &[PathBuf]) -> Vec<(PathBuf, Option<Stamp>)> {
    paths.iter().map(|p| (p.clone(), Stamp::of(p))).collect()
}

/// One route's replay and what it was made from.
#[derive(Debug)]
struct Entry {
    loaded: LoadedRecord,
    stamps: Vec<(PathBuf, Option<Stamp>)>,
    outcome: RouteOutcome,
}

/// How recent a file may be and still be trusted unchanged by its stamp, in `sds watch` and
/// `sds.watch` ([`RouteCache::new`], [`Watcher::new`]): a file rewritten within the same second
/// can keep its size and modification time.
pub const RACY: Duration = Duration::from_secs(1);

/// The routes' replays of earlier rounds, keyed by where the record sits (file, index) and
/// valid while the record (its whole content) is unchanged and so is every file and folder the
/// replay depended on: the telemetry files it read, or, when the telemetry was missing, the
/// folders where it was looked for (the absence of telemetry is cached like any other result).
/// Inputs shared by every route (the route XML, the maps) are the [`Watcher`]'s to check: it
/// empties the cache ([`RouteCache::clear`]) when one of them changes.
///
/// A file modified within `racy` of the moment it was stamped may have changed again within the
/// clock's resolution (git's "racily clean" problem): such a replay is not kept. Nor is one whose
/// telemetry could not be opened (a read error is never cached: a `chmod` mends it).
#[derive(Debug)]
pub struct RouteCache {
    racy: Duration,
    entries: Mutex<HashMap<(PathBuf, usize), Entry>>,
    seen: Mutex<HashSet<(PathBuf, usize)>>,
    durations: Mutex<HashMap<(PathBuf, usize), f64>>,
    changed: Mutex<Vec<String>>,
    rescored: AtomicUsize,
    reused: AtomicUsize,
}

/// What one round did with the cache ([`RouteCache::end_round`]).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct CacheRound {
    /// Routes replayed (new or changed, or not cacheable: a file too recent or unreadable).
    pub rescored: usize,
    /// Routes taken from the cache.
    pub reused: usize,
    /// The route ids replayed because they were new or changed, in no particular order.
    pub changed: Vec<String>,
}

impl RouteCache {
    /// An empty cache; `racy`: how recent a file may be and still be trusted unchanged
    /// (`sds watch` uses 1 s; a caller that writes nothing meanwhile can use zero).
    pub fn new(racy: Duration) -> Self {
        RouteCache {
            racy,
            entries: Mutex::default(),
            seen: Mutex::default(),
            durations: Mutex::default(),
            changed: Mutex::default(),
            rescored: AtomicUsize::new(0),
            reused: AtomicUsize::new(0),
        }
    }

    /// Ends a round: forgets the routes the round did not see (memory stays flat) and returns
    /// what the round did, counters reset.
    pub fn end_round(&self) -> CacheRound {
        let seen = std::mem::take(&mut *lock(&self.seen));
        lock(&self.entries).retain(|k, _| seen.contains(k));
        lock(&self.durations).retain(|k, _| seen.contains(k));
        CacheRound {
            rescored: self.rescored.swap(0, Ordering::Relaxed),
            reused: self.reused.swap(0, Ordering::Relaxed),
            changed: std::mem::take(&mut *lock(&self.changed)),
        }
    }

    /// Forgets every replay (an input shared by every route changed).
    pub fn clear(&self) {
        lock(&self.entries).clear();
    }

    /// Forgets what a round that came to nothing saw, keeping every replay (a retried round).
    pub fn abandon_round(&self) {
        lock(&self.seen).clear();
        lock(&self.changed).clear();
        self.rescored.store(0, Ordering::Relaxed);
        self.reused.store(0, Ordering::Relaxed);
    }

    /// Each route's `meta.duration_system` seen in the last round (wall-clock s), when recorded.
    pub fn durations(&self) -> Vec<f64> {
        lock(&self.durations).values().copied().collect()
    }

    /// The durations of [`RouteCache::durations`], by results file.
    pub fn durations_by_file(&self) -> HashMap<PathBuf, Vec<f64>> {
        let mut by: HashMap<PathBuf, Vec<f64>> = HashMap::new();
        for ((file, _), d) in lock(&self.durations).iter() {
            by.entry(file.clone()).or_default().push(*d);
        }
        by
    }
}

impl ReplayCache for RouteCache {
    /// The route's cached replay, or `replay()` (then kept unless a file it depends on is too
    /// recent or could not be opened).
    fn replay(&self, loaded: &LoadedRecord, replay: &dyn Fn() -> RouteOutcome) -> RouteOutcome {
        let key = (loaded.source.clone(), loaded.index);
        lock(&self.seen).insert(key.clone());
        if let Ok(r) = &loaded.entry {
            // A duration is the evaluator's wall-clock seconds: a negative or non-finite one (a
            // hand-edited `meta.duration_system`: -100 gave `seconds_left` -300) is left out of
            // the estimates (time left, stalled shards); a stale one is dropped.
            match r.meta.duration_system {
                Some(d) if d.is_finite() && d >= 0.0 => {
                    lock(&self.durations).insert(key.clone(), d);
                }
                _ => {
                    lock(&self.durations).remove(&key);
                }
            }
        }
        if let Some(e) = lock(&self.entries).get(&key) {
            let same =
                same_record(&e.loaded, loaded) && e.stamps.iter().all(|(p, s)| Stamp::of(p) == *s);
            if same {
                self.reused.fetch_add(1, Ordering::Relaxed);
                let mut o = e.outcome.clone();
                o.loaded = loaded.clone();
                return o;
            }
        }
        let outcome = replay();
        self.rescored.fetch_add(1, Ordering::Relaxed);
        if let Ok(r) = &loaded.entry {
            lock(&self.changed).push(r.route_id.clone());
        }
        let now = SystemTime::now();
        let depends: Vec<PathBuf> = outcome
            .files_read
            .iter()
            .chain(&outcome.looked_in)
            .cloned()
            .collect();
        let stamps = stamps(&depends);
        let settled = stamps
            .iter()
            .all(|(_, s)| Stamp::settled(s.as_ref(), now, self.racy));
        // A file located but not readable (permissions, gone): its error is not cached.
        let readable = outcome
            .files_read
            .iter()
            .all(|p| !p.is_file() || crate::input::read::open_nonblocking(p).is_ok());
        let mut entries = lock(&self.entries);
        if settled && readable {
            entries.insert(
                key,
                Entry {
                    loaded: loaded.clone(),
                    stamps,
                    outcome: outcome.clone(),
                },
            );
        } else {
            entries.remove(&key);
        }
        outcome
    }
}

/// The same record at the same place. The number of records in its file only matters as "one"
/// or "several" (telemetry beside a file of one record): a checkpoint growing by a record
/// leaves its earlier records unchanged.
fn same_record(a: &LoadedRecord, b: &LoadedRecord) -> bool {
    a.source == b.source
        && a.index == b.index
        && a.entry == b.entry
        && (a.records_in_file == 1) == (b.records_in_file == 1)
}

fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

/// What a round came to.
#[derive(Debug)]
#[allow(clippy::large_enum_variant)]
pub enum RoundOutcome {
    /// The inputs were read and scored.
    Scored {
        /// The report (with its breakdown and label maps, as `sds score`).
        scored: Box<Scored>,
        /// What the round replayed and reused.
        cache: CacheRound,
        /// Some results file or telemetry changed since the previous scored round.
        changed: bool,
        /// The round's status line.
        status: RoundStatus,
    },
    /// A results file was caught half-written (ends early, shrank, not there yet): retried next
    /// round, the last good reading kept.
    Retry {
        /// Why, naming the file.
        reason: String,
        /// Rounds in a row that failed so (a front end warns from 3 on).
        failures: usize,
        /// The round's status line: the figures of the last good reading, and `retry`.
        status: RoundStatus,
    },
}

/// The figures of a partial report (docs/USAGE.md §8's status line).
#[derive(Clone, Debug, PartialEq)]
pub struct WatchStatus {
    /// Routes with a record.
    pub done: usize,
    /// The benchmark's size N.
    pub n: usize,
    /// The scores over the routes done.
    pub over_done: Scores,
    /// The scores over N, the routes not done counting as 0.
    pub over_n: Scores,
    /// The set is complete: a route set is known (route XML or `expected_routes`) and every
    /// route has a record; without one, every results file is a checkpoint whose `progress`
    /// says done.
    pub complete: bool,
    /// Estimated seconds left: the mean `meta.duration_system` of the routes done times the
    /// routes left; with several shard checkpoints (one evaluator per GPU, side by side), times
    /// the routes left of the shard with the most to do (None without durations).
    pub seconds_left: Option<f64>,
}

/// The interval between rounds, checked: above 0 and at most [`MAX_INTERVAL`] s. The error
/// says the bound; the front end names its option.
///
/// ```
/// use monitor_host::app::watch::watcher::interval;
/// assert_eq!(interval(0.5).unwrap(), std::time::Duration::from_millis(500));
/// assert!(interval(1e19).unwrap_err().contains("86400"));
/// assert!(interval(f64::NAN).is_err() && interval(0.0).is_err());
/// ```
///
/// # Errors
/// Not a number in (0, [`MAX_INTERVAL`]].
pub fn interval(secs: f64) -> Result<Duration, String> {
    if secs > 0.0 && secs <= MAX_INTERVAL {
        Ok(Duration::from_secs_f64(secs))
    } else {
        Err(format!(
            "a number of seconds above 0 and at most {MAX_INTERVAL} (one day)"
        ))
    }
}

/// The timeout, checked: from 0 to [`MAX_TIMEOUT`] s.
///
/// ```
/// use monitor_host::app::watch::watcher::timeout;
/// assert_eq!(timeout(0.0).unwrap(), std::time::Duration::ZERO);
/// for bad in [f64::INFINITY, 1e300, f64::NAN, -5.0] {
///     assert!(timeout(bad).unwrap_err().contains("31536000"));
/// }
/// ```
///
/// # Errors
/// Not a number in [0, [`MAX_TIMEOUT`]].
pub fn timeout(secs: f64) -> Result<Duration, String> {
    if (0.0..=MAX_TIMEOUT).contains(&secs) {
        Ok(Duration::from_secs_f64(secs))
    } else {
        Err(format!(
            "a number of seconds from 0 to {MAX_TIMEOUT} (365 days)"
        ))
    }
}

/// The inputs every route shares, stamped: the route XML, and each OpenDRIVE map where
/// `--maps` looks (`<dir>/*.xodr`, `<dir>/OpenDrive/*.xodr`, `<dir>/<Town>/OpenDrive/*.xodr`).
type Shared = Vec<(PathBuf, Option<Stamp>)>;

/// A run kept current: the inputs of `sds score`, read again by every [`Watcher::round`].
#[derive(Debug)]
pub struct Watcher {
    inputs: Inputs,
    settings: Settings,
    labels: LabelFiles,
    by: Option<GroupBy>,
    racy: Duration,
    cache: RouteCache,
    sizes: HashMap<PathBuf, u64>,
    last_stamps: Vec<(PathBuf, Option<Stamp>)>,
    /// The shared inputs as the cached replays saw them; `None`: not to be trusted (too recent).
    shared: Option<Shared>,
    failures: usize,
    round: usize,
    /// The last good reading's status.
    last: RoundStatus,
    /// Each results file's `progress` by its stamp: read again only when the file changed.
    progress: Mutex<HashMap<PathBuf, Progress>>,
    /// K of [`crate::model::shard_stall`].
    stall_factor: f64,
}

impl Watcher {
    /// A watcher of `inputs`, scored as `sds score` would (`settings`, label files, breakdown);
    /// `racy` as in [`RouteCache::new`] (also how long a route XML, map or label file must be
    /// left unchanged before an error in it stops the watch).
    pub fn new(
        inputs: Inputs,
        settings: Settings,
        labels: LabelFiles,
        by: Option<GroupBy>,
        racy: Duration,
    ) -> Self {
        Watcher {
            inputs,
            settings,
            labels,
            by,
            racy,
            cache: RouteCache::new(racy),
            sizes: HashMap::new(),
            last_stamps: Vec::new(),
            shared: None,
            failures: 0,
            round: 0,
            last: RoundStatus::default(),
            progress: Mutex::new(HashMap::new()),
            stall_factor: crate::model::shard_stall::DEFAULT_FACTOR,
        }
    }

    /// K of [`crate::model::shard_stall`]: a shard is stalled after K times its median route time
    /// without a new record (default [`crate::model::shard_stall::DEFAULT_FACTOR`]).
    pub fn set_stall_factor(&mut self, k: f64) {
        self.stall_factor = k;
    }

    /// The shard checkpoints that stopped progressing, as of the last round's files.
    fn stalled(&self) -> Vec<crate::model::shard_stall::Stalled> {
        let durations = self.cache.durations_by_file();
        let shards: Vec<crate::model::shard_stall::Shard> = self
            .last_stamps
            .iter()
            .zip(self.file_progress())
            // A merged file is no shard.
            .filter_map(|((file, stamp), p)| {
                let (done, total) = p?;
                Some(crate::model::shard_stall::Shard {
                    file: file.clone(),
                    done,
                    total,
                    last_record: stamp.and_then(|s| s.modified),
                    durations: durations.get(file).cloned().unwrap_or_default(),
                })
            })
            .collect();
        crate::model::shard_stall::stalled_shards(&shards, SystemTime::now(), self.stall_factor)
    }

    /// One round: the results read again (a half-written, shrunk or absent file is a retry),
    /// each route replayed again only if something it depends on changed, the report made.
    ///
    /// ```
    /// use monitor_host::{demo, Inputs, LabelFiles, RoundOutcome, Settings, Watcher};
    ///
    /// let dir = tempfile::tempdir()?;
    /// let run = demo::write(dir.path())?;
    /// let inputs = Inputs { telemetry: Some(run.telemetry), ..Inputs::new([run.results.clone()]) };
    /// let mut w = Watcher::new(inputs, Settings::default(), LabelFiles::default(), None,
    ///                          std::time::Duration::ZERO);
    /// assert!(matches!(w.round()?, RoundOutcome::Scored { .. }));
    /// std::fs::write(&run.results, "{\"_checkpoint\": {\"reco")?; // caught half-written
    /// let RoundOutcome::Retry { failures: 1, status, .. } = w.round()? else { panic!() };
    /// assert_eq!(status.done, run.route_ids.len()); // the last good reading
    /// assert!(status.retry.is_some());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    ///
    /// # Errors
    /// The errors no later write of the evaluator can mend, as `sds score` stops on them:
    /// invalid settings, a `--telemetry` or `--maps` folder that does not exist, a route XML,
    /// map or label file that cannot be read or is invalid (once it has been left unchanged for
    /// `racy`), a label file not matching the grouping, duplicate route ids, a results file that
    /// is not JSON from its start (not a file being written) or not a checkpoint, an
    /// `expected_routes` below the routes counted.
    pub fn round(&mut self) -> Result<RoundOutcome, Error> {
        let began = std::time::Instant::now();
        self.round += 1;
        let files = results_files(&self.inputs.results);
        let stamps: Vec<(PathBuf, Option<Stamp>)> = stamps(&files);
        let mut shrunk = None;
        for (p, s) in &stamps {
            let len = s.map_or(0, |s| s.len);
            if self.sizes.get(p).is_some_and(|&before| len < before) {
                shrunk = Some(format!(
                    "{}: shorter than on the previous round ({} < {} bytes)",
                    p.display(),
                    len,
                    self.sizes[p]
                ));
            }
        }
        // Sizes are remembered even when the round is retried: a file that shrank for good
        // (a resume dropping a record) is accepted on the next round.
        for (p, s) in &stamps {
            self.sizes.insert(p.clone(), s.map_or(0, |s| s.len));
        }
        if let Some(reason) = shrunk {
            return Ok(self.retry(reason, began));
        }
        // A route XML or map changed (or may still be changing): no earlier replay is kept.
        let shared = self.shared_inputs();
        let now = SystemTime::now();
        let settled = shared
            .iter()
            .all(|(_, s)| Stamp::settled(s.as_ref(), now, self.racy));
        if self.shared.as_ref() != Some(&shared) {
            self.cache.clear();
        }
        self.shared = settled.then_some(shared);
        let result = score_labelled_cached(
            &self.inputs,
            &self.settings,
            &self.labels,
            self.by,
            &NoProgress,
            Some(&self.cache),
        );
        let scored = match result {
            Ok(s) => s,
            Err(e) if being_written(&e) || (user_file(&e) && !self.user_files_settled()) => {
                return Ok(self.retry(crate::error::message(&e), began))
            }
            Err(e) => {
                self.cache.abandon_round();
                return Err(e);
            }
        };
        // A file of a results folder caught half-written keeps the last good reading; one that
        // can never parse is an invalid row, as in `sds score`.
        if let Some(r) = scored.report.routes.iter().find(|r| {
            matches!(r.state, RouteState::Invalid(_))
                && r.route_id.is_none()
                && r.source.as_ref().is_some_and(|s| half_written(&s.file))
        }) {
            let reason = format!(
                "{}: {}",
                r.source
                    .as_ref()
                    .map_or_else(|| "-".into(), |s| s.file.display().to_string()),
                r.state
            );
            return Ok(self.retry(reason, began));
        }
        let cache = self.cache.end_round();
        let changed = cache.rescored > 0 || stamps != self.last_stamps;
        self.last_stamps = stamps;
        let p = self.progress(&scored.report);
        let mut status = self.status_line(&p, &scored.report, &cache, changed, began);
        status.stalled = self.stalled();
        self.failures = 0;
        self.last = status.clone();
        Ok(RoundOutcome::Scored {
            scored: Box::new(scored),
            cache,
            changed,
            status,
        })
    }

    fn retry(&mut self, reason: String, began: std::time::Instant) -> RoundOutcome {
        self.failures += 1;
        self.cache.abandon_round();
        let status = RoundStatus {
            round: self.round,
            time: utc(SystemTime::now()),
            rescored: 0,
            reused: 0,
            rescored_routes: Vec::new(),
            changed: false,
            retries: self.failures,
            round_ms: began.elapsed().as_secs_f64() * 1e3,
            stopped: None,
            retry: Some(reason.clone()),
            ..self.last.clone()
        };
        RoundOutcome::Retry {
            reason,
            failures: self.failures,
            status,
        }
    }

    /// The status line of the last round (scored or retried): the figures of the last good
    /// reading. A front end sets its `stopped` on the line it prints last.
    pub fn last_status(&self) -> &RoundStatus {
        &self.last
    }

    /// The round's status line.
    fn status_line(
        &self,
        p: &WatchStatus,
        report: &crate::model::Report,
        cache: &CacheRound,
        changed: bool,
        began: std::time::Instant,
    ) -> RoundStatus {
        // The last route: the last changed one in report order, else the last with a record.
        let last = report
            .routes
            .iter()
            .rev()
            .find(|r| {
                r.route_id
                    .as_ref()
                    .is_some_and(|id| cache.changed.contains(id))
            })
            .or_else(|| {
                report
                    .routes
                    .iter()
                    .rev()
                    .find(|r| !matches!(r.state, RouteState::Missing))
            });
        let mut ids = cache.changed.clone();
        ids.sort();
        RoundStatus {
            round: self.round,
            time: utc(SystemTime::now()),
            done: p.done,
            n: p.n,
            ds_done: p.over_done.driving_score,
            ds_n: p.over_n.driving_score,
            sds_done: p.over_done.sds,
            sds_n: p.over_n.sds,
            last_route: last.and_then(|r| r.route_id.clone()),
            last_state: last.map(|r| r.state.to_string()),
            last_ds: last.and_then(|r| r.score_composed),
            crashes: crate::report::rerun_list::crashes(report),
            seconds_left: p.seconds_left,
            rescored: cache.rescored,
            reused: cache.reused,
            rescored_routes: ids,
            changed,
            complete: p.complete,
            retries: self.failures,
            round_ms: began.elapsed().as_secs_f64() * 1e3,
            stopped: None,
            retry: None,
            stalled: Vec::new(),
        }
    }

    /// The route XML and the maps, stamped.
    fn shared_inputs(&self) -> Shared {
        let mut paths: Vec<PathBuf> = self.inputs.route_xml.iter().cloned().collect();
        if let Some(dir) = &self.inputs.maps {
            paths.push(dir.clone());
            let mut maps: Vec<PathBuf> = walkdir::WalkDir::new(dir)
                .min_depth(1)
                .max_depth(3)
                .into_iter()
                .filter_map(Result::ok)
                .filter(|e| {
                    e.file_type().is_dir()
                        || e.file_name()
                            .to_string_lossy()
                            .to_ascii_lowercase()
                            .ends_with(".xodr")
                })
                .map(|e| e.into_path())
                .collect();
            maps.sort();
            paths.extend(maps);
        }
        stamps(&paths)
    }

    /// The route XML, maps and label files have been left unchanged for `racy` (an error in one
    /// of them is then the user's to fix, not a file being copied).
    fn user_files_settled(&self) -> bool {
        let now = SystemTime::now();
        let labels: Vec<PathBuf> = self.labels.files().cloned().collect();
        self.shared_inputs()
            .iter()
            .chain(&stamps(&labels))
            .all(|(_, s)| Stamp::settled(s.as_ref(), now, self.racy))
    }

    /// The status figures of a report of this watch.
    pub fn progress(&self, report: &crate::model::Report) -> WatchStatus {
        let done: Vec<&crate::route::row::RouteReport> = report
            .routes
            .iter()
            .filter(|r| !matches!(r.state, RouteState::Missing))
            .collect();
        let n = report.summary.routes.max(done.len());
        let known_set = self.inputs.route_xml.is_some() || self.settings.expected_routes.is_some();
        let durations = self.cache.durations();
        let shards = self.file_progress();
        let left = n.saturating_sub(done.len()) as f64;
        // Shards run side by side: the run ends when the one with the most routes left does.
        // (A per-route file, `[1, 1]`, is not a shard.)
        let checkpoints: Vec<&(u64, u64)> = shards
            .iter()
            .flatten()
            .filter(|(_, total)| *total > 1)
            .collect();
        let shard_left = (checkpoints.len() > 1)
            .then(|| {
                checkpoints
                    .iter()
                    .map(|(i, total)| total.saturating_sub(*i))
                    .max()
            })
            .flatten()
            .map(|m| (m as f64).min(left));
        // Every shard done with routes still left: no evaluator watched here runs them, so the
        // time is unknown (it said "about 0m left" with 136 routes not started).
        let orphans = shard_left == Some(0.0) && left > 0.0;
        let seconds_left = (!durations.is_empty() && !orphans).then(|| {
            let mean = durations.iter().sum::<f64>() / durations.len() as f64;
            mean * shard_left.unwrap_or(left)
        });
        WatchStatus {
            done: done.len(),
            n,
            over_done: Scores::over(&done, done.len()),
            over_n: Scores::over(&done, n),
            // A merged file is a finished evaluation's: it never holds routes still to come.
            complete: if known_set {
                done.len() >= n
            } else {
                !shards.is_empty()
                    && shards
                        .iter()
                        .all(|p| p.is_none_or(|(i, total)| total > 1 && i >= total))
            },
            seconds_left,
        }
    }

    /// Each results file's `progress` `[done, total]` as of the last round (`[0, 0]` when it has
    /// none or does not read), read again only when the file changed. Without a route set the
    /// run is complete when every file is an evaluator's checkpoint of several routes whose
    /// progress says done (a per-route file, `[1, 1]`, says nothing about the routes still to
    /// come); several checkpoints are shards.
    fn file_progress(&self) -> Vec<Option<(u64, u64)>> {
        let mut known = lock(&self.progress);
        self.last_stamps
            .iter()
            .map(|(p, stamp)| match known.get(p) {
                Some((s, progress)) if s == stamp => *progress,
                _ => {
                    // None: a merged file (Bench2Drive's merge of a finished run), complete by
                    // itself; beside its raw files it is skipped, and never kept a watch of
                    // done shards running (issue 46 item 6).
                    let progress = match read_results(p) {
                        Ok(set) if !set.merged_totals.is_empty() => None,
                        read => Some(
                            read.ok()
                                .and_then(|set| set.files.first().and_then(|f| f.progress))
                                .unwrap_or((0, 0)),
                        ),
                    };
                    known.insert(p.clone(), (*stamp, progress));
                    progress
                }
            })
            .collect()
    }
}

/// An error a later write of the evaluator mends: a results file not there yet, unreadable,
/// ending early (truncated, then written), a folder without results yet, no record yet.
fn being_written(e: &Error) -> bool {
    matches!(
        e,
        Error::Results(
            ResultsError::Io { .. }
                | ResultsError::TruncatedJson { .. }
                | ResultsError::NoResults { .. }
        ) | Error::EmptyRun { .. }
    )
}

/// An error in a file the user gives (route XML, map, label file): retried while the file may
/// still be being written, else final.
fn user_file(e: &Error) -> bool {
    matches!(e, Error::RouteXml(_) | Error::Map(_) | Error::Labels(_))
}

/// A file of a results folder that is being written: gone or unreadable since it was listed,
/// or JSON that ends early (a prefix of a checkpoint always does).
fn half_written(path: &Path) -> bool {
    match crate::input::read::read_input(path, crate::input::read::FileKind::Results) {
        Err(_) => true,
        Ok(bytes) => serde_json::from_slice::<serde::de::IgnoredAny>(&bytes)
            .is_err_and(|e| e.classify() == serde_json::error::Category::Eof),
    }
}

/// `t` as an RFC 3339 UTC time to the second (`2026-11-27T17:45:33Z`).
///
/// ```
/// use std::time::{Duration, SystemTime};
/// let t = SystemTime::UNIX_EPOCH + Duration::from_secs(1_795_801_533);
/// assert_eq!(monitor_host::app::watch::watcher::utc(t), "2026-11-27T17:45:33Z");
/// ```
pub fn utc(t: SystemTime) -> String {
    let secs = t
        .duration_since(SystemTime::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    let (days, rest) = (secs / 86_400, secs % 86_400);
    // Days since 1970-01-01 to a civil date (Howard Hinnant's algorithm).
    let z = days as i64 + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!(
        "{year:04}-{month:02}-{day:02}T{:02}:{:02}:{:02}Z",
        rest / 3600,
        rest % 3600 / 60,
        rest % 60
    )
}

/// The results files to stamp: each file given, and the JSON files inside a folder given
/// (the shards and per-route files of an evaluation).
fn results_files(results: &[PathBuf]) -> Vec<PathBuf> {
    let mut files = Vec::new();
    for p in results {
        if p.is_dir() {
            let mut inside: Vec<PathBuf> = walkdir::WalkDir::new(p)
                .into_iter()
                .filter_map(Result::ok)
                .filter(|e| {
                    // Telemetry beside the records is stamped by the route cache instead.
                    let name = e.file_name().to_string_lossy();
                    e.file_type().is_file()
                        && name.to_ascii_lowercase().ends_with(".json")
                        && name != "metric_info.json"
                        && name != "infractions.json"
                })
                .map(|e| e.into_path())
                .collect();
            inside.sort();
            files.extend(inside);
        } else {
            files.push(p.clone());
        }
    }
    files
}

#[cfg(test)]
mod cache_tests {
    use super::*;
    use crate::app::run::score_run_cached;
    use crate::settings::Settings;

    /// A second round over unchanged files replays nothing and gives the same report.
    #[test]
    fn unchanged_round_replays_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let run = crate::demo::write(dir.path()).unwrap();
        let inputs = Inputs {
            telemetry: Some(run.telemetry),
            ..Inputs::new([run.results])
        };
        let cache = RouteCache::new(Duration::ZERO);
        let s = Settings::default();
        let first = score_run_cached(&inputs, &s, &NoProgress, Some(&cache)).unwrap();
        assert_eq!(cache.end_round().rescored, run.route_ids.len());
        let again = score_run_cached(&inputs, &s, &NoProgress, Some(&cache)).unwrap();
        assert_eq!(cache.end_round().rescored, 0);
        assert_eq!(first, again);
    }
}
