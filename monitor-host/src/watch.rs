//! Scoring an evaluation while it runs (`SDS-SPEC.md` v1.3 §12): the same run as `sds score`,
//! read again every round, each route replayed again only when its record or its telemetry
//! changed. [`Watcher::round`] is one round; `sds watch` (and any other front end) calls it in a
//! loop, renders each report and decides when to stop.
//!
//! An evaluator rewrites its checkpoint in place, not atomically, so a round may find a file
//! half-written: a results file that does not parse, or that is shorter than on the previous
//! round, makes the round a [`RoundOutcome::Retry`] (the previous report stays current), never
//! an error.

use std::collections::{HashMap, HashSet};
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::{Duration, SystemTime};

use crate::aggregate::aggregates::Scores;
use crate::aggregate::groups::GroupBy;
use crate::error::Error;
use crate::input::record::LoadedRecord;
use crate::input::results_file::read_results;
use crate::pipeline::outcome::{RouteOutcome, RouteState, TelemetryState};
use crate::run::{Inputs, NoProgress, ReplayCache};
use crate::scored::{score_labelled_cached, LabelFiles, Scored};
use crate::settings::Settings;

/// A results file's `progress` `[done, total]`, and the stamp of the file it was read from.
type Progress = (Option<Stamp>, (u64, u64));

/// A file's size and modification time: what tells a changed file (spec §12).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Stamp {
    len: u64,
    modified: Option<SystemTime>,
}

impl Stamp {
    fn of(path: &std::path::Path) -> Option<Stamp> {
        let m = std::fs::metadata(path).ok()?;
        Some(Stamp {
            len: m.len(),
            modified: m.modified().ok(),
        })
    }
}

/// One route's replay and what it was made from.
#[derive(Debug)]
struct Entry {
    loaded: LoadedRecord,
    stamps: Vec<(PathBuf, Option<Stamp>)>,
    outcome: RouteOutcome,
}

/// The routes' replays of earlier rounds, keyed by where the record sits (file, index) and
/// valid while the record (its whole content) and every telemetry file the replay read (size
/// and modification time) are unchanged.
///
/// A file modified within `racy` of the moment it was stamped may have changed again within the
/// clock's resolution (git's "racily clean" problem): such a replay is not kept.
///
/// ```
/// use monitor_host::{demo, score_run_cached, Inputs, NoProgress, RouteCache, Settings};
///
/// let dir = tempfile::tempdir()?;
/// let run = demo::write(dir.path())?;
/// let inputs = Inputs { telemetry: Some(run.telemetry), ..Inputs::new([run.results]) };
/// let cache = RouteCache::new(std::time::Duration::ZERO);
/// let first = score_run_cached(&inputs, &Settings::default(), &NoProgress, Some(&cache))?;
/// assert_eq!(cache.end_round().rescored, run.route_ids.len());
/// let again = score_run_cached(&inputs, &Settings::default(), &NoProgress, Some(&cache))?;
/// assert_eq!(cache.end_round().rescored, 0); // nothing changed: nothing replayed
/// assert_eq!(first, again);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
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
    /// Routes replayed (new or changed, or not cacheable: no telemetry yet).
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
}

impl ReplayCache for RouteCache {
    /// The route's cached replay, or `replay()` (then kept when it read telemetry that is not
    /// too recent).
    fn replay(&self, loaded: &LoadedRecord, replay: &dyn Fn() -> RouteOutcome) -> RouteOutcome {
        let key = (loaded.source.clone(), loaded.index);
        lock(&self.seen).insert(key.clone());
        if let Ok(r) = &loaded.entry {
            if let Some(d) = r.meta.duration_system {
                lock(&self.durations).insert(key.clone(), d);
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
        // Missing telemetry may appear at any time, under a name only discovery knows: never
        // cached. Telemetry read (good or half-written) is cached by its files' stamps.
        let read = !matches!(outcome.telemetry, TelemetryState::Missing(_))
            && !outcome.files_read.is_empty();
        let now = SystemTime::now();
        let stamps: Vec<(PathBuf, Option<Stamp>)> = outcome
            .files_read
            .iter()
            .map(|p| (p.clone(), Stamp::of(p)))
            .collect();
        let settled = stamps.iter().all(|(_, s)| {
            s.and_then(|s| s.modified)
                .and_then(|m| now.duration_since(m).ok())
                .is_some_and(|age| age >= self.racy)
        });
        let mut entries = lock(&self.entries);
        if read && settled {
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
    },
    /// A results file was caught half-written (does not parse, or shrank): retried next round.
    Retry {
        /// Why, naming the file.
        reason: String,
        /// Rounds in a row that failed so (a front end warns from 3 on).
        failures: usize,
    },
}

/// The figures of a partial report (spec §12's status line).
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

/// A run kept current: the inputs of `sds score`, read again by every [`Watcher::round`].
#[derive(Debug)]
pub struct Watcher {
    inputs: Inputs,
    settings: Settings,
    labels: LabelFiles,
    by: Option<GroupBy>,
    cache: RouteCache,
    sizes: HashMap<PathBuf, u64>,
    last_stamps: Vec<(PathBuf, Option<Stamp>)>,
    failures: usize,
    /// Each results file's `progress` by its stamp: read again only when the file changed.
    progress: Mutex<HashMap<PathBuf, Progress>>,
}

impl Watcher {
    /// A watcher of `inputs`, scored as `sds score` would (`settings`, label files, breakdown);
    /// `racy` as in [`RouteCache::new`].
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
            cache: RouteCache::new(racy),
            sizes: HashMap::new(),
            last_stamps: Vec::new(),
            failures: 0,
            progress: Mutex::new(HashMap::new()),
        }
    }

    /// One round: the results read again (a half-written or shrunk file is a retry), each
    /// route replayed again only if it changed, the report made.
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
    /// assert!(matches!(w.round()?, RoundOutcome::Retry { failures: 1, .. }));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    ///
    /// # Errors
    /// The errors a later round cannot mend: invalid settings, a `--telemetry` or `--maps`
    /// folder that does not exist, a label file not matching the grouping.
    pub fn round(&mut self) -> Result<RoundOutcome, Error> {
        let files = results_files(&self.inputs.results);
        let stamps: Vec<(PathBuf, Option<Stamp>)> =
            files.iter().map(|p| (p.clone(), Stamp::of(p))).collect();
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
            return Ok(self.retry(reason));
        }
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
            Err(e) if fatal(&e) => return Err(e),
            Err(e) => return Ok(self.retry(crate::error::message(&e))),
        };
        // A file of a results folder that does not parse is most likely being written.
        if self.failures < 3 {
            if let Some(r) = scored
                .report
                .routes
                .iter()
                .find(|r| matches!(r.state, RouteState::Invalid(_)) && r.route_id.is_none())
            {
                let reason = format!(
                    "{}: {}",
                    r.source
                        .as_ref()
                        .map_or_else(|| "-".into(), |s| s.file.display().to_string()),
                    r.state
                );
                return Ok(self.retry(reason));
            }
        }
        self.failures = 0;
        let cache = self.cache.end_round();
        let changed = cache.rescored > 0 || stamps != self.last_stamps;
        self.last_stamps = stamps;
        Ok(RoundOutcome::Scored {
            scored: Box::new(scored),
            cache,
            changed,
        })
    }

    fn retry(&mut self, reason: String) -> RoundOutcome {
        self.failures += 1;
        self.cache.abandon_round();
        RoundOutcome::Retry {
            reason,
            failures: self.failures,
        }
    }

    /// The status figures of a report of this watch.
    pub fn progress(&self, report: &crate::Report) -> WatchStatus {
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
        let checkpoints: Vec<&(u64, u64)> = shards.iter().filter(|(_, total)| *total > 1).collect();
        let shard_left = (checkpoints.len() > 1)
            .then(|| {
                checkpoints
                    .iter()
                    .map(|(i, total)| total.saturating_sub(*i))
                    .max()
            })
            .flatten()
            .map(|m| (m as f64).min(left));
        let seconds_left = (!durations.is_empty()).then(|| {
            let mean = durations.iter().sum::<f64>() / durations.len() as f64;
            mean * shard_left.unwrap_or(left)
        });
        WatchStatus {
            done: done.len(),
            n,
            over_done: Scores::over(&done, done.len()),
            over_n: Scores::over(&done, n),
            complete: if known_set {
                done.len() >= n
            } else {
                !shards.is_empty() && shards.iter().all(|(i, total)| *total > 1 && i >= total)
            },
            seconds_left,
        }
    }

    /// Each results file's `progress` `[done, total]` as of the last round (`[0, 0]` when it has
    /// none or does not read), read again only when the file changed. Without a route set the
    /// run is complete when every file is an evaluator's checkpoint of several routes whose
    /// progress says done (a per-route file, `[1, 1]`, says nothing about the routes still to
    /// come); several checkpoints are shards.
    fn file_progress(&self) -> Vec<(u64, u64)> {
        let mut known = lock(&self.progress);
        self.last_stamps
            .iter()
            .map(|(p, stamp)| match known.get(p) {
                Some((s, progress)) if s == stamp => *progress,
                _ => {
                    let progress = read_results(p)
                        .ok()
                        .and_then(|set| set.files.first().and_then(|f| f.progress))
                        .unwrap_or((0, 0));
                    known.insert(p.clone(), (*stamp, progress));
                    progress
                }
            })
            .collect()
    }
}

/// Errors no later round can mend (usage errors).
fn fatal(e: &Error) -> bool {
    matches!(
        e,
        Error::Settings(_)
            | Error::TelemetryRoot { .. }
            | Error::MapsFolder { .. }
            | Error::NeedsLabels(_)
            | Error::UnusedLabels
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
