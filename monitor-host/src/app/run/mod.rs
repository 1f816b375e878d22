//! A run scored route by route, what every command that scores shares (docs/USAGE.md): the
//! commands' requests ([`crate::app::score`], [`crate::app::compare`], [`crate::app::watch`],
//! [`crate::app::frames`], [`crate::app::link`]) call it; no command of its own.
//!
//! Beside it: [`scored`] (the label files read and checked around a scored run), [`scored_by`]
//! (a saved report read back), [`vehicle_logs`] (MCAP logs and rosbag2 folders scored),
//! [`rerun`] (the routes to run again), [`diagnostics`] (the notes about a scored run).

pub mod diagnostics;
pub mod rerun;
pub mod scored;
pub mod scored_by;
pub mod vehicle_logs;

use std::path::{Path, PathBuf};

use rayon::prelude::*;

use crate::error::Error;
use crate::geometry::town_maps::TownMaps as Maps;
use crate::geometry::town_maps::{town_of, TownMaps};
use crate::input::duplicates::{
    deduplicate, earlier_attempts, save_name_stamp, Deduplicated, DuplicatePolicy, Kept, Source,
};
use crate::input::record::{InvalidRecord, LoadedRecord};
use crate::input::results_file::{read_results, InputFile, ResultSet};
use crate::input::route_set::{benchmark_size, route_set, route_subset};
use crate::input::route_xml::read_route_xml;
use crate::input::route_xml::RouteSet;
use crate::input::stored::check_inputs;
use crate::model::report::{assemble_rows, Report, RunFacts};
use crate::pipeline::outcome::{RouteOutcome, TelemetryState};
use crate::pipeline::replay::{read_telemetry, replay, replay_points, RouteContext};
use crate::provenance::Provenance;
use crate::route::row::{outcome_row, route_rows, RouteReport};
use crate::settings::Settings;

use crate::input::warning::Warning;
pub use crate::model::frames::RouteFrames;

/// The files of a run.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Inputs {
    /// Results: raw evaluator files, merged files, or directories of per-route files, read in
    /// this order (docs/SCORE.md §14.1's input order).
    pub results: Vec<PathBuf>,
    /// Telemetry root holding `<save_name>/metric_info.json`.
    pub telemetry: Option<PathBuf>,
    /// Bench2Drive route XML: the lateral reference, the route set (missing and foreign routes,
    /// N) and the abilities' scenario types.
    pub route_xml: Option<PathBuf>,
    /// Folder of the towns' OpenDRIVE maps (docs/SCORE.md §14.3).
    pub maps: Option<PathBuf>,
}

impl Inputs {
    /// Inputs with these results files and nothing else.
    pub fn new<I: IntoIterator<Item = P>, P: Into<PathBuf>>(results: I) -> Self {
        Inputs {
            results: results.into_iter().map(Into::into).collect(),
            ..Inputs::default()
        }
    }
}

/// Hears how far a run is: [`Progress::start`] once with the number of routes, then
/// [`Progress::route_done`] once per route, from the worker threads. For a progress bar, or for
/// bindings that report progress or check for interruption.
pub trait Progress: Sync {
    /// The routes are read: `routes` will be scored.
    fn start(&self, routes: usize) {
        let _ = routes;
    }
    /// One more route is scored (called from a worker thread, in any order).
    fn route_done(&self) {}
    /// True once the run should stop: checked before each route (from the worker threads); the
    /// routes not started then are not scored and the run ends with [`Error::Cancelled`]. A
    /// binding sets it on Ctrl-C, which it can only see on its own thread.
    fn cancelled(&self) -> bool {
        false
    }
}

/// Keeps routes' replays between runs (`sds watch`'s [`crate::app::watch::watcher::RouteCache`]): given a
/// record, returns its earlier replay when nothing it was made from changed, else calls
/// `replay`.
pub trait ReplayCache: Sync {
    /// The replay of `loaded`: kept, or made by `replay`.
    fn replay(&self, loaded: &LoadedRecord, replay: &dyn Fn() -> RouteOutcome) -> RouteOutcome;
}

/// A [`Progress`] that ignores everything.
#[derive(Clone, Copy, Debug, Default)]
pub struct NoProgress;

impl Progress for NoProgress {}

/// Scores a run: reads the results (and the route XML), replays every route through the
/// streaming monitor on a thread pool, checks it against the batch reference, and builds the
/// report.
///
/// The commands call it through their requests ([`crate::ScoreRequest`], which also adds the
/// notes about the run and reads the label files); it stays public as the door at typed
/// [`Settings`] that the tests and benchmarks call with a field set directly.
///
/// A front end decides its exit status from the report's data ([`Report::has_problems`],
/// [`Report::problem_routes`]), never from its rendering.
///
/// ```
/// use monitor_host::{demo, score_run, Inputs, Settings};
///
/// let dir = tempfile::tempdir()?;
/// let run = demo::write(dir.path())?;
/// let inputs = Inputs {
///     telemetry: Some(run.telemetry),
///     route_xml: Some(run.routes),
///     ..Inputs::new([run.results])
/// };
/// let report = score_run(&inputs, &Settings::default())?;
/// assert_eq!(report.routes.len(), run.route_ids.len());
/// assert!(report.summary.scores.sds.is_some());
/// assert!(!report.has_problems());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// [`Error`] when no report can be made: invalid settings, unreadable results or route XML.
pub fn score_run(inputs: &Inputs, settings: &Settings) -> Result<Report, Error> {
    score_run_with(inputs, settings, &NoProgress)
}

/// [`score_run`], telling `progress` how far it is.
///
/// # Errors
/// As [`score_run`].
pub(crate) fn score_run_with(
    inputs: &Inputs,
    settings: &Settings,
    progress: &dyn Progress,
) -> Result<Report, Error> {
    score_run_cached(inputs, settings, progress, None)
}

/// [`score_run_with`], taking each route's replay from `cache` when neither its record nor its
/// telemetry files changed since the cache saw them (`sds watch`). The report
/// is the same as without the cache.
///
/// # Errors
/// As [`score_run`].
pub(crate) fn score_run_cached(
    inputs: &Inputs,
    settings: &Settings,
    progress: &dyn Progress,
    cache: Option<&dyn ReplayCache>,
) -> Result<Report, Error> {
    let mut reports = score_points(inputs, std::slice::from_ref(settings), progress, cache)?;
    Ok(reports.remove(0))
}

/// Scores a run at several points of `sds compare --sweep` (one report per point, in order,
/// each the report [`score_run`] gives at that point), reading the results, the route XML and
/// the maps once and each route's telemetry once per distinct input to its preparation
/// ([`crate::pipeline::replay::replay_points`]). The points may differ only in settings that
/// change a route's figures ([`crate::settings::defs::sweep_names`]); the first point's decide
/// the rest (the duplicates policy, the route set, N).
///
/// # Errors
/// As [`score_run`] (any point's invalid settings included).
pub(crate) fn score_run_points(
    inputs: &Inputs,
    points: &[Settings],
    progress: &dyn Progress,
) -> Result<Vec<Report>, Error> {
    score_points(inputs, points, progress, None)
}

/// [`score_run_points`], a single point taking its replays from `cache` when given.
fn score_points(
    inputs: &Inputs,
    points: &[Settings],
    progress: &dyn Progress,
    cache: Option<&dyn ReplayCache>,
) -> Result<Vec<Report>, Error> {
    let Some(settings) = points.first() else {
        return Ok(Vec::new());
    };
    for p in points {
        p.validate()?;
    }
    if let Some(root) = &inputs.telemetry {
        check_telemetry_root(root)?;
    }
    if let Some(dir) = &inputs.maps {
        check_maps_folder(dir)?;
    }
    let mut warnings = Vec::new();
    let (sets, all) = read_inputs(&inputs.results, &mut warnings)?;
    let files_read: Vec<PathBuf> = sets
        .iter()
        .flat_map(|s| s.files_read.iter().cloned())
        .collect();
    if all.is_empty() {
        return Err(Error::EmptyRun {
            inputs: inputs.results.clone(),
        });
    }
    let kept = keep_one_copy(&all, &sets, settings, &mut warnings)?;
    let records = kept.records;
    let routes = inputs
        .route_xml
        .as_deref()
        .map(read_route_xml)
        .transpose()?;
    let set = routes.as_ref().map(|xml| {
        let set = route_set(xml, records.iter().filter_map(|r| route_id_of(r)));
        route_subset(set, settings.route_subset)
    });
    let (foreign, n) = foreign_and_n(&records, set.as_ref(), settings)?;
    let input_reports = check_inputs(&sets, &all, n, &mut warnings);
    // Every copy of the records but the kept ones is done with: a run's memory holds one record
    // per route while it replays.
    drop(all);
    drop(sets);

    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(settings.worker_threads(records.len()))
        .build()?;
    let towns: Vec<Option<&str>> = records
        .iter()
        .map(|r| {
            r.entry
                .as_ref()
                .ok()
                .and_then(|rec| town_of(rec, routes.as_ref()))
        })
        .collect();
    let maps = pool.install(|| {
        TownMaps::load(
            inputs.maps.as_deref(),
            towns.iter().flatten().map(|t| t.to_string()),
        )
    })?;
    // Each point's map warnings now: `towns` borrows the records, which move into their tasks.
    let point_warnings: Vec<Vec<Warning>> = points
        .iter()
        .map(|p| map_warnings(&maps, &towns, p))
        .collect();
    drop(towns);
    progress.start(records.len());
    let telemetry = inputs.telemetry.as_deref();
    let xml = routes.as_ref();
    // Per route, one `Done` per point, in point order.
    let done: Vec<Option<Vec<Done>>> = pool.install(|| {
        // Each record is moved into its route's task and dropped with it.
        records
            .into_par_iter()
            .zip(&foreign)
            .map(|(r, &foreign)| {
                if progress.cancelled() {
                    return None;
                }
                let town = r.entry.as_ref().ok().and_then(|rec| town_of(rec, xml));
                let map = town.and_then(|t| maps.get(t).ok());
                let r = &r;
                let outcomes = match (cache, points) {
                    (Some(c), [_]) => {
                        vec![c.replay(r, &|| replay(r, xml, map, telemetry, settings))]
                    }
                    (None, [_]) => vec![replay(r, xml, map, telemetry, settings)],
                    _ => replay_points(r, xml, map, telemetry, points),
                };
                // The route's rows now, and its outcomes dropped: what a run holds per route is
                // its row at each point, not its timeline or record.
                let rows = outcomes
                    .into_iter()
                    .zip(points)
                    .map(|(mut o, p)| {
                        o.foreign = foreign;
                        Done::of(o, p, xml, &maps)
                    })
                    .collect();
                release_freed_pages();
                progress.route_done();
                Some(rows)
            })
            .collect()
    });
    let Some(done) = done.into_iter().collect::<Option<Vec<_>>>() else {
        return Err(Error::Cancelled);
    };
    // One list of rows per point, in record order.
    let mut per_point: Vec<Vec<Done>> = points
        .iter()
        .map(|_| Vec::with_capacity(done.len()))
        .collect();
    for route in done {
        for (list, d) in per_point.iter_mut().zip(route) {
            list.push(d);
        }
    }
    let run = RunRead {
        inputs,
        files_read,
        routes: xml,
        set,
        n,
        input_reports,
        dropped: kept.dropped,
        kept: kept.kept,
        warnings,
        maps: &maps,
    };
    Ok(points
        .iter()
        .zip(per_point)
        .zip(point_warnings)
        .map(|((settings, done), map_warnings)| run.report(done, settings, map_warnings))
        .collect())
}

/// The duplicates policy applied to every record read, with the warnings it raises: copies
/// scored or left out, the newest chosen by input order, year wraps and earlier attempts.
fn keep_one_copy(
    all: &[LoadedRecord],
    sets: &[ResultSet],
    settings: &Settings,
    warnings: &mut Vec<Warning>,
) -> Result<Deduplicated, Error> {
    let mut kept = deduplicate(all.to_vec(), settings.duplicates)?;
    if settings.duplicates == DuplicatePolicy::All && !kept.duplicates.is_empty() {
        warnings.push(Warning::DuplicatesScored {
            ids: kept.duplicates.len(),
            first: kept.duplicates.iter().take(5).cloned().collect(),
        });
    }
    if !kept.dropped.is_empty() {
        warnings.push(Warning::DuplicatesDropped {
            copies: kept.dropped.len(),
            ids: kept.duplicates.len(),
            policy: settings.duplicates.name(),
        });
    }
    let by_order: Vec<String> = kept
        .kept
        .iter()
        .filter(|k| k.by_order)
        .map(|k| {
            let r = all.iter().find(|r| Source::of(r) == k.source);
            r.and_then(route_id_of).unwrap_or_default().to_string()
        })
        .collect();
    if !by_order.is_empty() {
        warnings.push(Warning::NewestByOrder { routes: by_order });
    }
    note_year_wraps_and_earlier_attempts(&mut kept, all, sets, settings, warnings);
    Ok(kept)
}

/// Per record, whether it is foreign to the route set; and N, the benchmark's size: an error
/// when N is smaller than the routes counted.
fn foreign_and_n(
    records: &[LoadedRecord],
    set: Option<&crate::input::route_set::RunRouteSet>,
    settings: &Settings,
) -> Result<(Vec<bool>, usize), Error> {
    let foreign: Vec<bool> = records
        .iter()
        .map(|r| {
            set.zip(route_id_of(r))
                .is_some_and(|(s, id)| !s.contains(id))
        })
        .collect();
    let missing = set.map_or(0, |s| s.missing.len());
    // Under a route set, an entry without a route id (an unreadable file) is most likely one of
    // the missing routes: it is reported, but not counted against N a second time.
    let counted = records
        .iter()
        .zip(&foreign)
        .filter(|(r, f)| !**f && (set.is_none() || route_id_of(r).is_some()))
        .count()
        + missing;
    // Under `duplicates: all` every copy counts in N.
    let extra_copies = records.len() - kept_ids(records);
    let n = benchmark_size(settings.expected_routes, set, counted)
        + if settings.expected_routes.is_none() && set.is_some() {
            extra_copies
        } else {
            0
        };
    if n < counted {
        return Err(Error::TooFewRoutes {
            n,
            counted,
            missing,
            from_option: settings.expected_routes.is_some(),
        });
    }
    Ok((foreign, n))
}

/// What a run read before its routes were replayed: the rest of its report, at each point.
struct RunRead<'a> {
    inputs: &'a Inputs,
    files_read: Vec<PathBuf>,
    routes: Option<&'a RouteSet>,
    set: Option<crate::input::route_set::RunRouteSet>,
    n: usize,
    input_reports: Vec<crate::input::stored::InputReport>,
    dropped: Vec<crate::input::duplicates::Dropped>,
    kept: Vec<Kept>,
    warnings: Vec<Warning>,
    maps: &'a TownMaps,
}

impl RunRead<'_> {
    /// The report of the routes' rows at one point.
    fn report(&self, done: Vec<Done>, settings: &Settings, map_warnings: Vec<Warning>) -> Report {
        let inputs = self.inputs;
        let maps = self.maps;
        let set = &self.set;
        let mut warnings = self.warnings.clone();
        warnings.extend(map_warnings);
        for d in done.iter().filter(|d| d.foreign) {
            warnings.push(Warning::ForeignRoute {
                route: d.route_id.clone().unwrap_or_default(),
                routes_file: inputs.route_xml.clone().unwrap_or_default(),
            });
        }
        let without = done
            .iter()
            .filter(|d| !d.foreign && d.missing.is_some())
            .count();
        let with = done.iter().filter(|d| d.telemetry_ok).count();
        if without > 0 && with == 0 && !settings.allow_missing_telemetry {
            // With a root given, one route's reason shows what was looked for (and the closest
            // folder); without one, the message itself says so.
            let example = inputs
                .telemetry
                .as_ref()
                .and_then(|_| done.iter().find_map(|d| d.missing.clone()));
            warnings.push(Warning::NoTelemetry {
                root: inputs.telemetry.clone(),
                routes: without,
                example,
            });
        }
        // The per-route stage (rows, traces, abilities), then the aggregates over its rows.
        let missing = set.as_ref().map_or(&[][..], |s| &s.missing[..]);
        let mut rows = Vec::with_capacity(done.len() + missing.len());
        let mut route_files = Vec::new();
        for d in done {
            rows.push(d.row);
            route_files.extend(d.files_read);
        }
        rows.extend(route_rows(&[], missing, settings, self.routes, maps));
        let provenance = Provenance::new(
            settings,
            self.files_read
                .iter()
                .map(|f| (f.as_path(), "results"))
                .chain(inputs.route_xml.iter().map(|f| (f.as_path(), "routes")))
                .chain(maps.files().iter().map(|f| (f.as_path(), "map"))),
        );
        let facts = RunFacts {
            provenance,
            n: self.n,
            route_set: set.clone(),
            inputs: self.input_reports.clone(),
            dropped: self.dropped.clone(),
            kept: self.kept.clone(),
            warnings,
        };
        let mut report = assemble_rows(rows, settings, facts);
        // Every input file, for front ends that must never write over one.
        let mut files = self.files_read.clone();
        files.extend(inputs.route_xml.iter().cloned());
        files.extend(maps.files().iter().cloned());
        files.append(&mut route_files);
        files.sort();
        files.dedup();
        report.files_read = files;
        report
    }
}

/// Gives the pages a finished route freed back to the system, every [`TRIM_EVERY`] routes of a
/// thread. A route's transient buffers (its telemetry file, its frames) are freed between the
/// small allocations of the rows kept: the allocator's heap cannot shrink past those, so without
/// this a run's resident memory grows with its routes although what it holds does not.
fn release_freed_pages() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        use std::cell::Cell;
        thread_local!(static ROUTES: Cell<u32> = const { Cell::new(0) });
        let n = ROUTES.with(|c| {
            c.set(c.get().wrapping_add(1));
            c.get()
        });
        if n.is_multiple_of(TRIM_EVERY) {
            // SAFETY: malloc_trim only returns free memory to the system; it takes no pointer.
            #[allow(unsafe_code)]
            unsafe {
                libc::malloc_trim(0);
            }
        }
    }
}

/// Routes of a thread between two [`release_freed_pages`] calls.
const TRIM_EVERY: u32 = 16;

/// What a run keeps of a replayed route: its row, and the few facts the run's warnings and file
/// list need. The outcome itself is dropped when its route is done.
struct Done {
    row: RouteReport,
    files_read: Vec<PathBuf>,
    route_id: Option<String>,
    foreign: bool,
    /// Counted, and its telemetry was replayed.
    telemetry_ok: bool,
    /// A valid record without telemetry found: its route id and why.
    missing: Option<(String, String)>,
}

impl Done {
    fn of(o: RouteOutcome, settings: &Settings, xml: Option<&RouteSet>, maps: &Maps) -> Done {
        let missing = match (&o.telemetry, o.record()) {
            (TelemetryState::Missing(why), Some(r)) => Some((r.route_id.clone(), why.clone())),
            _ => None,
        };
        Done {
            row: outcome_row(&o, settings, xml, maps),
            route_id: route_id_of(&o.loaded).map(String::from),
            foreign: o.foreign,
            telemetry_ok: o.counted() && o.telemetry == TelemetryState::Ok,
            missing,
            files_read: o.files_read,
        }
    }
}

/// A telemetry root that does not exist is a mistyped path, not a run without telemetry.
fn check_telemetry_root(root: &Path) -> Result<(), Error> {
    let reason = match std::fs::metadata(root) {
        Ok(m) if m.is_dir() => return Ok(()),
        Ok(_) => "not a folder".to_string(),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => "no such folder".to_string(),
        Err(e) => e.to_string(),
    };
    Err(Error::TelemetryRoot {
        given_as: "telemetry",
        path: root.to_path_buf(),
        reason,
    })
}

/// A `--maps` folder that does not exist is a mistyped path, not a run without maps.
fn check_maps_folder(dir: &Path) -> Result<(), Error> {
    let reason = match std::fs::metadata(dir) {
        Ok(m) if m.is_dir() => return Ok(()),
        Ok(_) => "not a folder".to_string(),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => "no such folder".to_string(),
        Err(e) => e.to_string(),
    };
    Err(Error::MapsFolder {
        path: dir.to_path_buf(),
        reason,
    })
}

/// Reads every results input in the order given: the sets (one per input) and every record
/// (an unreadable file in a directory is an invalid entry: its routes are unknown, but nothing
/// found is silently lost).
fn read_inputs(
    paths: &[PathBuf],
    warnings: &mut Vec<Warning>,
) -> Result<(Vec<ResultSet>, Vec<LoadedRecord>), Error> {
    let mut sets = Vec::new();
    let mut records = Vec::new();
    for path in paths {
        let mut set = read_results(path)?;
        warnings.append(&mut set.warnings);
        records.extend(set.records.iter().cloned());
        records.extend(
            set.broken_files
                .iter()
                .map(|(source, reason)| LoadedRecord {
                    source: source.clone(),
                    index: 0,
                    records_in_file: 0,
                    entry: Err(InvalidRecord {
                        route_id: None,
                        reason: reason.clone(),
                    }),
                }),
        );
        sets.push(set);
    }
    Ok((sets, records))
}

/// The duplicates policy's notes beyond the copy it kept: routes whose stamps could wrap a year
/// (`newest`), and, under `newest` or `last`, records kept from an earlier attempt because the
/// newer run that re-ran their file did not finish ([`earlier_attempts`]): each such route's
/// `kept` says so, and one warning per file.
fn note_year_wraps_and_earlier_attempts(
    kept: &mut Deduplicated,
    all: &[LoadedRecord],
    sets: &[ResultSet],
    settings: &Settings,
    warnings: &mut Vec<Warning>,
) {
    let wrapped: Vec<String> = kept
        .kept
        .iter()
        .filter(|k| k.year_wrap)
        .filter_map(|k| all.iter().find(|r| Source::of(r) == k.source))
        .filter_map(|r| route_id_of(r).map(String::from))
        .collect();
    if !wrapped.is_empty() {
        warnings.push(Warning::NewestYearWrap { routes: wrapped });
    }
    if !matches!(
        settings.duplicates,
        DuplicatePolicy::Newest | DuplicatePolicy::Last
    ) {
        return;
    }
    let files: Vec<InputFile> = sets.iter().flat_map(|s| s.files.iter().cloned()).collect();
    for a in earlier_attempts(kept, &files) {
        for (_, source) in &a.routes {
            let stamp = kept
                .records
                .iter()
                .find(|r| Source::of(r) == *source)
                .and_then(|r| r.entry.as_ref().ok())
                .and_then(|r| r.save_name.as_deref())
                .and_then(save_name_stamp);
            kept.kept.push(Kept {
                policy: settings.duplicates.name(),
                copies: 1,
                stamp: stamp.map(|s| s.map(|x| format!("{x:02}")).join("_")),
                why: format!(
                    "the only record, from the earlier attempt {}: the newer run {} re-ran this \
                     file's routes but holds no record of this one (it did not finish)",
                    a.earlier.display(),
                    a.newer.display()
                ),
                source: source.clone(),
                by_order: false,
                year_wrap: false,
            });
        }
        warnings.push(Warning::EarlierAttempt {
            routes: a.routes.into_iter().map(|(id, _)| id).collect(),
            newer: a.newer,
            progress: a.progress,
            earlier: a.earlier,
        });
    }
}

/// A record's route id, valid or not.
fn route_id_of(r: &LoadedRecord) -> Option<&str> {
    match &r.entry {
        Ok(rec) => Some(&rec.route_id),
        Err(e) => e.route_id.as_deref(),
    }
}

/// Distinct route ids among the records (records without one count once each).
fn kept_ids(records: &[LoadedRecord]) -> usize {
    let mut ids = std::collections::HashSet::new();
    records
        .iter()
        .filter(|r| route_id_of(r).is_none_or(|id| ids.insert(id)))
        .count()
}

/// The frames of the route `route_id` (`RouteScenario_<id>_rep<k>`): the first valid record
/// with this id in the results, its telemetry read and prepared.
///
/// # Errors
/// As [`score_run`], or [`Error::NoRoute`], [`Error::InvalidRecord`], [`Error::Telemetry`].
pub fn route_frames(
    inputs: &Inputs,
    route_id: &str,
    settings: &Settings,
) -> Result<RouteFrames, Error> {
    let (kept, routes, files_read) = frame_records(inputs, settings)?;
    // The copy `score` would stream: the duplicate rule picks it.
    let mut copies = kept
        .into_iter()
        .filter(|r| r.entry.as_ref().is_ok_and(|r| r.route_id == route_id));
    let loaded = copies.next().ok_or_else(|| Error::NoRoute {
        file: inputs.results.first().cloned().unwrap_or_default(),
        route: route_id.into(),
    })?;
    let others = copies.count();
    if others > 0 {
        return Err(Error::AmbiguousRoute {
            route: route_id.into(),
            copies: others + 1,
        });
    }
    let Ok(record) = &loaded.entry else {
        return Err(Error::InvalidRecord {
            route: route_id.into(),
        });
    };
    let town = town_of(record, routes.as_ref());
    if let Some(dir) = &inputs.maps {
        check_maps_folder(dir)?;
    }
    let maps = TownMaps::load(inputs.maps.as_deref(), town.map(str::to_string))?;
    let mut files_read = files_read;
    files_read.extend(maps.files().iter().cloned());
    frames_of(
        &loaded,
        inputs,
        settings,
        routes.as_ref(),
        &maps,
        files_read,
    )
}

/// One record's frames (or why it has none), keyed by its source.
pub type SourcedFrames = (Source, Result<RouteFrames, Error>);

/// The frames of every valid record the duplicate rule keeps, each keyed by its source (file
/// and index, as the report's `source`): what `sds score --tables` writes as `frames`. The
/// results, route XML and maps are read once; a route whose telemetry cannot be read has its
/// error in place of its frames.
///
/// # Errors
/// As [`score_run`] (the inputs as a whole).
pub fn run_frames(inputs: &Inputs, settings: &Settings) -> Result<Vec<SourcedFrames>, Error> {
    Ok(named_frames(inputs, settings)?
        .into_iter()
        .map(|(_, frames)| frames)
        .collect())
}

/// [`run_frames`], each with its record's route id: `sds link` names the routes it plays
/// without reading the results files again.
pub(crate) fn named_frames(
    inputs: &Inputs,
    settings: &Settings,
) -> Result<Vec<(String, SourcedFrames)>, Error> {
    let (kept, routes, files_read) = frame_records(inputs, settings)?;
    if let Some(dir) = &inputs.maps {
        check_maps_folder(dir)?;
    }
    let towns: Vec<String> = kept
        .iter()
        .filter_map(|l| l.entry.as_ref().ok())
        .filter_map(|r| town_of(r, routes.as_ref()).map(str::to_string))
        .collect();
    let maps = TownMaps::load(inputs.maps.as_deref(), towns)?;
    let files_read: Vec<PathBuf> = files_read
        .into_iter()
        .chain(maps.files().iter().cloned())
        .collect();
    Ok(kept
        .par_iter()
        .filter_map(|l| Some((l, l.entry.as_ref().ok()?.route_id.clone())))
        .map(|(l, id)| {
            let frames = frames_of(
                l,
                inputs,
                settings,
                routes.as_ref(),
                &maps,
                files_read.clone(),
            );
            (id, (Source::of(l), frames))
        })
        .collect())
}

/// The records `score` would stream (the duplicate rule applied), the route XML and the files
/// read, for [`route_frames`] and [`run_frames`].
#[allow(clippy::type_complexity)]
fn frame_records(
    inputs: &Inputs,
    settings: &Settings,
) -> Result<
    (
        Vec<LoadedRecord>,
        Option<crate::input::route_xml::RouteSet>,
        Vec<PathBuf>,
    ),
    Error,
> {
    settings.validate()?;
    let mut records = Vec::new();
    let mut files_read = Vec::new();
    for path in &inputs.results {
        let set = read_results(path)?;
        records.extend(set.records);
        files_read.extend(set.files_read);
    }
    files_read.extend(inputs.route_xml.iter().cloned());
    let routes = inputs
        .route_xml
        .as_deref()
        .map(read_route_xml)
        .transpose()?;
    let kept = deduplicate(records, settings.duplicates)?;
    Ok((kept.records, routes, files_read))
}

/// One valid record's frames: its telemetry read and prepared as [`score_run`] streams it.
fn frames_of(
    loaded: &LoadedRecord,
    inputs: &Inputs,
    settings: &Settings,
    routes: Option<&crate::input::route_xml::RouteSet>,
    maps: &TownMaps,
    mut files_read: Vec<PathBuf>,
) -> Result<RouteFrames, Error> {
    let route_id = route_id_of(loaded).unwrap_or_default().to_string();
    let Ok(record) = &loaded.entry else {
        return Err(Error::InvalidRecord { route: route_id });
    };
    let town = town_of(record, routes);
    let mut warnings = Vec::new();
    let context = RouteContext {
        routes,
        map: town.and_then(|t| maps.get(t).ok()),
        telemetry_root: inputs.telemetry.as_deref(),
        settings,
        keep_lateral: true,
    };
    let telemetry = read_telemetry(loaded, record, context, &mut warnings, &mut files_read)
        .map_err(|state| Error::Telemetry {
            route: route_id.clone(),
            state,
        })?;
    Ok(RouteFrames {
        frames: telemetry.prepared.frames,
        steps: telemetry.prepared.steps,
        lateral: telemetry.prepared.lateral,
        reference: telemetry.prepared.reference,
        dt: telemetry.settings.core.dt,
        warnings,
        files_read,
    })
}

/// One warning per town that has routes but no map, when a `--maps` folder is given or the
/// `lane` reference is asked for (which needs one), naming how many routes fall back.
fn map_warnings(maps: &TownMaps, towns: &[Option<&str>], settings: &Settings) -> Vec<Warning> {
    let lane = settings.lateral_reference == crate::settings::LateralReference::Lane;
    if !maps.given() && !lane {
        return Vec::new();
    }
    let mut count: std::collections::BTreeMap<&str, usize> = Default::default();
    for t in towns.iter().flatten() {
        *count.entry(t).or_default() += 1;
    }
    let absent: Vec<(&str, usize, String)> = count
        .into_iter()
        .filter_map(|(town, routes)| Some((town, routes, maps.get(town).err()?)))
        .collect();
    // Several towns in one line: a run over CARLA's 12 towns with a few maps is one fact.
    match &absent[..] {
        [] => Vec::new(),
        [(town, routes, reason)] => vec![Warning::NoMap {
            town: town.to_string(),
            routes: *routes,
            reason: reason.clone(),
            lane_fallback: lane,
        }],
        [(_, _, reason), ..] => vec![Warning::NoMaps {
            towns: absent.iter().map(|(t, n, _)| (t.to_string(), *n)).collect(),
            reason: reason.clone(),
            lane_fallback: lane,
        }],
    }
}

#[cfg(test)]
mod points_tests {
    use super::*;

    /// Each point's report is the one `score_run` gives at that point.
    #[test]
    fn points_score_as_single_runs() {
        let dir = tempfile::tempdir().unwrap();
        let run = crate::demo::write(dir.path()).unwrap();
        let inputs = Inputs {
            telemetry: Some(run.telemetry),
            ..Inputs::new([run.results])
        };
        let mut strict = Settings::default();
        strict.set("critical_excess", "0.3").unwrap();
        let points = [Settings::default(), strict.clone()];
        let reports = score_run_points(&inputs, &points, &NoProgress).unwrap();
        assert_eq!(
            reports[1].summary,
            score_run(&inputs, &strict).unwrap().summary
        );
        assert_eq!(reports.len(), 2);
        assert_eq!(
            reports[0].summary,
            score_run(&inputs, &Settings::default()).unwrap().summary
        );
    }
}
