//! Warnings: problems that do not stop a run or a route from being scored. Typed, naming the
//! file and route they concern; the report prints them with [`std::fmt::Display`].

use std::path::PathBuf;

use crate::input::collision::CollisionList;
use crate::input::route_xml::RouteError;
use crate::input::source::Duplicate;

/// One warning. Run-level warnings sit in [`crate::Report::warnings`], route-level ones in
/// each route's `warnings`.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum Warning {
    /// A results file with no records (a crashed or empty run).
    NoRecords {
        /// The results file.
        file: PathBuf,
        /// Its `entry_status`, if any.
        entry_status: Option<String>,
        /// Its `progress`, as written (`[0, 220]`), if any.
        progress: Option<String>,
        /// The run stopped before any route finished.
        crashed: bool,
    },
    /// Fewer records than the file's `progress` total: the run did not finish.
    Unfinished {
        /// The results file.
        file: PathBuf,
        /// Its `progress`, as written.
        progress: String,
        /// Records found.
        recorded: usize,
        /// The progress total.
        total: u64,
    },
    /// A merged file's stored totals could not be read.
    StoredTotalsIgnored {
        /// The merged file.
        file: PathBuf,
        /// Why.
        reason: String,
    },
    /// A record whose `score_composed` is not `score_route * score_penalty` (see
    /// [`crate::input::record::Record::composed_mismatch`]).
    ComposedScore {
        /// The results file.
        file: PathBuf,
        /// The record's index in it.
        index: usize,
        /// The route id.
        route: String,
        /// `score_route`, `score_penalty`, `score_composed`.
        scores: [f64; 3],
    },
    /// A record with a status the evaluator does not write.
    UnknownStatus {
        /// The results file.
        file: PathBuf,
        /// The record's index in it.
        index: usize,
        /// The route id.
        route: String,
        /// The status.
        status: String,
    },
    /// A results file in a directory that could not be read (it is reported as an invalid
    /// route).
    UnreadableResults {
        /// The full reason, naming the file.
        reason: String,
    },
    /// A merged file skipped because raw evaluator files lie beside it.
    MergedSkipped {
        /// The merged file.
        file: PathBuf,
        /// How many raw files were found.
        raw_files: usize,
    },
    /// A folder that could not be listed.
    CannotList {
        /// The folder.
        dir: PathBuf,
        /// The OS error.
        reason: String,
    },
    /// A directory entry that could not be read (e.g. a dangling link).
    CannotRead {
        /// The entry.
        path: PathBuf,
        /// The OS error.
        reason: String,
    },
    /// A folder link under a results root that leads out of it (not followed: it would pull in
    /// another run's results).
    LinkLeavesRoot {
        /// The link.
        link: PathBuf,
        /// Where it leads.
        target: PathBuf,
    },
    /// Under `duplicates: all`, route ids scored more than once.
    DuplicatesScored {
        /// How many ids have more than one copy.
        ids: usize,
        /// The first few of them, with the sources of each copy.
        first: Vec<Duplicate>,
    },
    /// Copies of duplicated routes left out by `duplicates: first|last|newest` (listed in
    /// `dropped`).
    DuplicatesDropped {
        /// Copies left out.
        copies: usize,
        /// Route ids concerned.
        ids: usize,
        /// `first`, `last` or `newest`.
        policy: &'static str,
    },
    /// Under `duplicates: newest`, routes whose copies could not all be ordered by their
    /// `save_name` time stamps (a tie, or a stamp missing): the last copy in input order kept.
    NewestByOrder {
        /// The route ids.
        routes: Vec<String>,
    },
    /// Under `duplicates: newest`, routes whose copies' `save_name` stamps lie more than half a
    /// year apart (they carry no year, so they could wrap one): the copy of the most recently
    /// modified file, or the checkpoint's own record order, was kept.
    NewestYearWrap {
        /// The route ids.
        routes: Vec<String>,
    },
    /// Routes whose record comes from an earlier attempt: a newer results file that re-ran this
    /// file's routes (its copies were kept over this file's) did not finish, and holds no record
    /// of them.
    EarlierAttempt {
        /// The newer, unfinished file.
        newer: PathBuf,
        /// Its `progress`, `[done, total]`.
        progress: (u64, u64),
        /// The file the kept records come from.
        earlier: PathBuf,
        /// The route ids.
        routes: Vec<String>,
    },
    /// A record whose route is not in the route set of `--routes` (docs/SCORE.md §14.1).
    ForeignRoute {
        /// The route id.
        route: String,
        /// The route XML.
        routes_file: PathBuf,
    },
    /// An input file's stored figures differ from the ones computed over its records.
    StoredFigures {
        /// The file.
        file: PathBuf,
        /// `driving score` or `success rate`.
        what: &'static str,
        /// The stored value (success rate in percent).
        stored: f64,
        /// What the stored value's denominator seems to be.
        stored_denominator: String,
        /// The computed value with the run's N.
        computed: f64,
        /// The run's N.
        n: usize,
    },
    /// A route whose step period fits no multiple of the 0.05 s tick (docs/SCORE.md §2.2).
    StepPeriodUnknown {
        /// Step span `last - first + 1`.
        span: u64,
        /// `meta.duration_game`, s.
        duration_game: f64,
        /// The `dt` used instead.
        dt: f64,
    },
    /// A route whose missing steps exceed 10 % of its span, so that its period is not inferred
    /// (docs/SCORE.md §2.2, v1.3): the file holds only part of the run.
    StepPeriodPartial {
        /// Missing step numbers.
        gaps: u64,
        /// Step span.
        span: u64,
        /// The `dt` used instead.
        dt: f64,
    },
    /// A route whose missing steps exceed 10 % of its span.
    LargeGaps {
        /// Missing step numbers.
        gaps: u64,
        /// Step span.
        span: u64,
    },
    /// No route of the run has telemetry (said once instead of once per route).
    NoTelemetry {
        /// The telemetry root given, if any.
        root: Option<PathBuf>,
        /// Routes without telemetry.
        routes: usize,
        /// The first such route and why its telemetry was not found.
        example: Option<(String, String)>,
    },
    /// A label file that misses some routes' keys.
    LabelsMissKeys {
        /// The label file.
        file: PathBuf,
        /// The keys without a label (the first few).
        keys: Vec<String>,
        /// How many keys in all.
        count: usize,
    },
    /// A warning about one route.
    Route {
        /// The route id (or the source when the record has none).
        route: String,
        /// The warning.
        warning: Box<Warning>,
    },
    /// A merge output whose `eval num` is not its number of records.
    EvalNum {
        /// The file.
        file: PathBuf,
        /// Its `eval num`.
        eval_num: u64,
        /// Its records.
        records: usize,
    },
    /// LEAD's `infractions.json` beside the telemetry is unreadable.
    LeadInfractions {
        /// The file.
        file: PathBuf,
        /// Why.
        reason: String,
    },
    /// Every segment of the route's reference is longer than `gap_max`: the lateral error is
    /// unknown on the whole route.
    AllGaps {
        /// The route XML.
        file: String,
        /// The XML route id.
        route: String,
        /// The `gap_max` setting.
        gap_max: f64,
    },
    /// The route XML has no usable reference for this route.
    NoReference(RouteError),
    /// A town with routes has no map in the `--maps` folder (once per town): its routes are
    /// measured against the route XML (docs/SCORE.md §14.3, docs/SCORE.md §3).
    NoMap {
        /// The town.
        town: String,
        /// How many of the run's routes are in it.
        routes: usize,
        /// Where the map was looked for.
        reason: String,
        /// `lateral_reference = lane` was asked for and falls back to `route`.
        lane_fallback: bool,
    },
    /// Several towns with routes have no map in the `--maps` folder: said in one line (a
    /// [`Warning::NoMap`] when it is one town).
    NoMaps {
        /// Each town and how many of the run's routes are in it, in town order.
        towns: Vec<(String, usize)>,
        /// Where the first town's map was looked for.
        reason: String,
        /// `lateral_reference = lane` was asked for and falls back to `route`.
        lane_fallback: bool,
    },
    /// The town's map does not serve this route (no driving lane, or its lanes lie far from
    /// the route's frames: a wrong or moved map): the route is measured against the route XML
    /// instead ([`crate::geometry::map_fit`]).
    MapNotServing {
        /// The map file.
        file: String,
        /// The town.
        town: String,
        /// The median distance (m) from the frames to the nearest driving lane; `None` when the
        /// map has no driving lane.
        distance: Option<f64>,
        /// The farthest a map's lanes may lie from a route it serves, m (`map_fit::MAP_REACH`).
        reach: f64,
        /// `lateral_reference = lane` was asked for and falls back to `route`.
        lane_fallback: bool,
    },
    /// A collision string that does not parse.
    UnparseableCollision {
        /// Its list.
        list: CollisionList,
        /// Why.
        reason: String,
    },
    /// Routes whose group key has no label in the label map: grouped as `(unmapped)` (docs/SCORE.md §10.2).
    Unmapped {
        /// The grouping (`family`, `weather`).
        by: &'static str,
        /// The first few keys that matched nothing.
        keys: Vec<String>,
        /// Routes concerned.
        routes: usize,
    },
    /// A route term a scoring protocol could not read as the spec wants (docs/PROTOCOLS.md): what was
    /// skipped or approximated.
    Protocol(String),
    /// Records whose min-speed entries were regrouped on Bench2Drive's 20-checkpoint grid under
    /// the Leaderboard protocols (docs/PROTOCOLS.md v1.4, "The min-speed grid").
    MinSpeedRegrouped {
        /// Records on the 20-checkpoint grid.
        records: usize,
        /// Records with protocol scores.
        of: usize,
        /// The `min_speed_grid` setting.
        setting: &'static str,
        /// The asked protocols that regroup (`lb2.0`, `lb2.1`, `lead-nds`).
        protocols: Vec<&'static str>,
    },
    /// Routes that count as Fail2Drive successes though they did not finish: `RC < 100` or a
    /// failed status (docs/PROTOCOLS.md v1.4; Fail2Drive's rule reads only the infraction lists).
    F2dUnfinished {
        /// Their route ids, in report order.
        routes: Vec<String>,
    },
    /// A route's warning as a report wrote it (a part of `sds merge` read back, docs/SCORE.md §13.2):
    /// printed unchanged.
    Recorded(String),
    /// A vehicle log's note (docs/SCORE.md §2.4): messages lost to a cut, sorted out of order,
    /// clock gaps, the IMU replaced by the odometry twist, no Leaderboard record.
    VehicleLog {
        /// The MCAP file (or rosbag2 folder); empty for a note about every log of the run.
        file: PathBuf,
        /// What happened and what it means.
        text: String,
    },
    /// A warning of a part of `sds merge` (docs/SCORE.md §13.2), naming the part.
    Part {
        /// The part's file.
        part: PathBuf,
        /// The warning as the part wrote it.
        text: String,
    },
    /// A note: routes whose inferred step period is not CARLA's 0.05 s tick (docs/SCORE.md, the
    /// step period): a period read wrong would scale every speed and time of a route.
    PeriodInferred {
        /// The period inferred, s.
        dt: f64,
        /// The routes (ids) inferred at it.
        routes: Vec<String>,
    },
    /// A note: aligned collisions past the first [`crate::route::trace::TRACES_PER_ROUTE`] of
    /// a route have no trace (every collision is still in the report's events).
    Untraced {
        /// Collisions without a trace.
        collisions: usize,
        /// Traces kept per route.
        cap: usize,
    },
}

impl Warning {
    /// True for a note: a fact worth saying that asks nothing of the user (the `sds` command
    /// prints it after `sds: note: `).
    ///
    /// A note read back from a report (a part of `sds merge`, a saved run of `sds compare`)
    /// stays a note: the JSON report keeps warnings and notes as text, so it is known by how
    /// its text ends.
    ///
    /// ```
    /// use monitor_host::Warning;
    /// let note = Warning::Untraced { collisions: 2, cap: 8 };
    /// assert!(note.is_note());
    /// assert!(Warning::Recorded(note.to_string()).is_note());
    /// assert!(!Warning::Recorded("a warning".into()).is_note());
    /// ```
    pub fn is_note(&self) -> bool {
        match self {
            Warning::PeriodInferred { .. } | Warning::Untraced { .. } => true,
            Warning::Route { warning, .. } => warning.is_note(),
            Warning::Recorded(text) | Warning::Part { text, .. } => {
                NOTE_ENDS.iter().any(|end| text.ends_with(end))
            }
            _ => false,
        }
    }
}

/// How the notes' texts end ([`Warning::PeriodInferred`], [`Warning::Untraced`]), written by
/// their `Display` and read by [`Warning::is_note`] for a note read back as text.
const NOTE_ENDS: [&str; 2] = [
    " (the setting dt=SECONDS fixes the period of every route)",
    "; every collision is in the JSON report's events)",
];

impl std::fmt::Display for Warning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        // One match over every variant, by family: a new variant cannot compile without its
        // text.
        match self {
            // The results files and what was read from them: records, stored figures,
            // unreadable or skipped files.
            Warning::NoRecords {
                file,
                entry_status,
                progress,
                crashed,
            } => {
                write!(f, "{}: no records", file.display())?;
                let details: Vec<String> = entry_status
                    .iter()
                    .map(|s| format!("entry_status {s}"))
                    .chain(progress.iter().map(|p| format!("progress {p}")))
                    .collect();
                if !details.is_empty() {
                    write!(f, " ({})", details.join(", "))?;
                }
                if *crashed {
                    f.write_str(": the run crashed before any route finished")?;
                }
                Ok(())
            }
            Warning::Unfinished {
                file,
                progress,
                recorded,
                total,
            } => write!(
                f,
                "{}: progress {progress} but only {recorded} of {total} routes recorded: the run \
                 did not finish",
                file.display()
            ),
            Warning::StoredTotalsIgnored { file, reason } => {
                write!(f, "{}: stored totals ignored: {reason}", file.display())
            }
            Warning::UnknownStatus {
                file,
                index,
                route,
                status,
            } => write!(
                f,
                "{}: record {index} ({route}): unknown status {status:?} (counted as not \
                 successful)",
                file.display()
            ),
            Warning::ComposedScore {
                file,
                index,
                route,
                scores: [r, p, c],
            } => write!(
                f,
                "{}: record {index} ({route}): score_composed {c} is not score_route {r} x score_penalty {p} = {} (edited record? SDS uses score_route and score_penalty)",
                file.display(),
                r * p
            ),
            Warning::UnreadableResults { reason } => {
                write!(f, "skipped unreadable results file: {reason}")
            }
            Warning::MergedSkipped { file, raw_files } => write!(
                f,
                "{}: skipped: a Bench2Drive merged file (has \"driving score\") beside {raw_files} \
                 raw evaluator file(s); reading both would count its routes twice",
                file.display()
            ),
            Warning::CannotList { dir, reason } => {
                write!(f, "{}: cannot list: {reason}", dir.display())
            }
            Warning::LinkLeavesRoot { link, target } => write!(
                f,
                "{}: a folder link leading out of the results folder (to {}): not followed",
                link.display(),
                target.display()
            ),
            Warning::CannotRead { path, reason } => {
                write!(f, "{}: cannot read: {reason}", path.display())
            }
            Warning::StoredFigures {
                file,
                what,
                stored,
                stored_denominator,
                computed,
                n,
            } => write!(
                f,
                "{}: stored {what} {stored} ({stored_denominator}) differs from the computed \
                 {computed} over the file's records divided by N = {n}",
                file.display()
            ),
            Warning::EvalNum {
                file,
                eval_num,
                records,
            } => write!(
                f,
                "{}: eval num {eval_num} but {records} records in the file: the merge counted \
                 route(s) whose record it did not keep (with a route XML, every route of the set \
                 without a record is listed as missing)",
                file.display()
            ),
            Warning::LeadInfractions { file, reason } => write!(
                f,
                "{}: {reason}; collisions aligned by position instead",
                file.display()
            ),
            Warning::UnparseableCollision { list, reason } => write!(
                f,
                "{}: unparseable collision string ({reason}): counted, not aligned",
                list.name()
            ),
            // Which copy of a route was kept (the duplicates policy) and routes outside the
            // route set.
            Warning::DuplicatesScored { ids, first } => write!(
                f,
                "duplicates: all: {ids} route id(s) scored more than once, each copy counts in N \
                 (duplicates = newest|first|last keeps one): {}{}",
                first
                    .iter()
                    .map(ToString::to_string)
                    .collect::<Vec<_>>()
                    .join("; "),
                if *ids > first.len() { "; ..." } else { "" }
            ),
            Warning::DuplicatesDropped {
                copies,
                ids,
                policy,
            } => write!(
                f,
                "duplicates: {policy}: {copies} {} of {ids} route id{} left out; the report's \
                 `dropped` lists each with the copy kept, each route's `kept` says why",
                if *copies == 1 { "copy" } else { "copies" },
                if *ids == 1 { "" } else { "s" }
            ),
            Warning::NewestByOrder { routes } => write!(
                f,
                "duplicates: newest: {} route id(s) kept by input order (the last copy), their \
                 copies' save_name time stamps tied or unreadable: {} (each route's `kept` says \
                 why)",
                routes.len(),
                id_list(routes)
            ),
            Warning::NewestYearWrap { routes } => write!(
                f,
                "duplicates: newest: {} route id(s) have copies whose save_name time stamps \
                 (mm_dd_HH_MM_SS, no year) lie more than half a year apart and could wrap a year \
                 (a December run and a January re-run): the copy in the most recently modified \
                 file was kept (in one file, the checkpoint's own record order): {} (each \
                 route's `kept` says which; duplicates = first|last chooses by input order)",
                routes.len(),
                id_list(routes)
            ),
            Warning::EarlierAttempt {
                newer,
                progress,
                earlier,
                routes,
            } => write!(
                f,
                "{} route(s) keep their record from the earlier attempt {}: the newer run {} \
                 (kept over it for the routes it re-ran) holds no record of them{}: {}",
                routes.len(),
                earlier.display(),
                newer.display(),
                format_args!(
                    " (progress {} of {}: it crashed or stopped before finishing)",
                    progress.0, progress.1
                ),
                id_list(routes)
            ),
            Warning::ForeignRoute { route, routes_file } => write!(
                f,
                "{route} is not in the route set of {} (a foreign route): reported, left out of \
                 every aggregate",
                routes_file.display()
            ),
            // The telemetry: its step period, its gaps, none found.
            Warning::StepPeriodUnknown {
                span,
                duration_game,
                dt,
            } => write!(
                f,
                "step period unknown: {span} steps for duration_game {duration_game} s fit no \
                 multiple of 0.05 s; dt {dt} s used (fix it with the setting dt=SECONDS)"
            ),
            Warning::StepPeriodPartial { gaps, span, dt } => write!(
                f,
                "step period not inferred: {gaps} of {span} step numbers missing (over 10 %), \
                 the telemetry holds only part of the run; dt {dt} s used (set the agent's \
                 period with the setting dt=SECONDS); its chunks span missing time"
            ),
            Warning::PeriodInferred { dt, routes } => write!(
                f,
                "step period inferred as {dt} s (not the 0.05 s tick) for {} route(s): {}{}",
                routes.len(),
                id_list(routes),
                NOTE_ENDS[0]
            ),
            Warning::Untraced { collisions, cap } => write!(
                f,
                "{collisions} more collision(s) without a trace (at most {cap} per route{}",
                NOTE_ENDS[1]
            ),
            Warning::LargeGaps { gaps, span } => write!(
                f,
                "{gaps} of {span} step numbers missing (over 10 %): its chunks span missing time"
            ),
            Warning::NoTelemetry {
                root,
                routes,
                example,
            } => {
                match root {
                    Some(r) => write!(
                        f,
                        "no route has telemetry: none of the {routes} route(s) has \
                         <save_name>/metric_info.json under {}",
                        r.display()
                    )?,
                    None => write!(
                        f,
                        "no route has telemetry: none of the {routes} route(s) has a \
                         metric_info.json beside its results file, and no telemetry folder was given"
                    )?,
                }
                if let Some((route, reason)) = example {
                    write!(f, " (e.g. {route}: {reason})")?;
                }
                f.write_str(
                    "; give the telemetry folder, the one holding <save_name>/metric_info.json \
                     (telemetry), or allow_missing_telemetry to score without telemetry terms",
                )
            }
            // The lateral reference: maps that are absent or serve no route, routes without one.
            Warning::AllGaps {
                file,
                route,
                gap_max,
            } => write!(
                f,
                "{file}: route {route}: every segment is longer than gap_max = {gap_max} m (all \
                 junction gaps): lateral excess unknown for this route (denser waypoints, or \
                 the setting gap_max=<metres>)"
            ),
            Warning::NoReference(e) => write!(f, "{e}: lateral excess unknown for this route"),
            Warning::NoMap {
                town,
                routes,
                reason,
                lane_fallback,
            } => {
                let s = if *routes == 1 { "" } else { "s" };
                write!(
                    f,
                    "{reason}: the {routes} route{s} in {town} fall back to the route XML's \
                     straight segments (junction gaps unscored, every lane `lane_width` wide)"
                )?;
                if *lane_fallback {
                    f.write_str("; lateral_reference=lane needs a map and falls back to route")?;
                }
                f.write_str("; add the town's .xodr to the maps folder to use its lanes")
            }
            Warning::NoMaps {
                towns,
                reason,
                lane_fallback,
            } => {
                let listed: Vec<String> = towns
                    .iter()
                    .map(|(t, n)| format!("{t} ({n} route{})", if *n == 1 { "" } else { "s" }))
                    .collect();
                let routes: usize = towns.iter().map(|(_, n)| n).sum();
                write!(
                    f,
                    "no map for {} towns: {} ({reason}; the same for the others): their {routes} \
                     routes fall back to the route XML's straight segments (junction gaps \
                     unscored, every lane `lane_width` wide)",
                    towns.len(),
                    id_list(&listed)
                )?;
                if *lane_fallback {
                    f.write_str("; lateral_reference=lane needs a map and falls back to route")?;
                }
                f.write_str("; add the towns' .xodr to the maps folder to use their lanes")
            }
            Warning::MapNotServing {
                file,
                town,
                distance,
                reach,
                lane_fallback,
            } => {
                match distance {
                    None => write!(f, "{file}: the map of {town} has no driving lane")?,
                    Some(d) => write!(
                        f,
                        "{file}: the map of {town} does not serve this route: its frames lie \
                         {d:.1} m (median) from the nearest driving lane, more than {reach} m (a \
                         wrong or moved map?)"
                    )?,
                }
                f.write_str(
                    "; the map is not used for this route: measured against the route XML's \
                     straight segments",
                )?;
                if *lane_fallback {
                    f.write_str("; lateral_reference=lane needs a map and falls back to route")?;
                }
                Ok(())
            }
            // Label files, groups and the scoring protocols.
            Warning::LabelsMissKeys { file, keys, count } => write!(
                f,
                "{}: no label for {count} key(s) ({}{}): those routes fall in \"(unmapped)\"",
                file.display(),
                keys.join(", "),
                if *count > keys.len() { ", ..." } else { "" }
            ),
            Warning::Unmapped { by, keys, routes } => write!(
                f,
                "group_by = {by}: {routes} route(s) whose key has no label are grouped as \
                 \"(unmapped)\"; keys without a label: {}",
                keys.join(", ")
            ),
            Warning::Protocol(what) => write!(f, "protocols: {what}"),
            Warning::MinSpeedRegrouped {
                records,
                of,
                setting,
                protocols,
            } => write!(
                f,
                "protocols: {records} of {of} records hold Bench2Drive's 20 min-speed checkpoints \
                 (min_speed_grid={setting}): under {} their entries were regrouped by 5 into one \
                 Leaderboard checkpoint each, at the group's harmonic mean; each route's \
                 min_speed_grid and min_speed_events say which and how many (the \
                 setting min_speed_grid=lb-4 charges every entry below 100 %)",
                protocols.join(", ")
            ),
            Warning::F2dUnfinished { routes } => write!(
                f,
                "protocols: f2d: {} route(s) count as Fail2Drive successes though they did not \
                 finish (route completion below 100 or a failed status): Fail2Drive's rule reads \
                 only the infraction lists: {}",
                routes.len(),
                id_list(routes)
            ),
            // Texts passed on: a route's, a part's, a report's read back, a vehicle log's.
            Warning::Route { route, warning } => write!(f, "{route}: {warning}"),
            Warning::Recorded(text) => f.write_str(text),
            Warning::Part { part, text } => write!(f, "part {}: {text}", part.display()),
            Warning::VehicleLog { file, text } if file.as_os_str().is_empty() => f.write_str(text),
            Warning::VehicleLog { file, text } => write!(f, "{}: {text}", file.display()),
        }
    }
}

pub use crate::input::source::IDS_SHOWN;

/// A list of route ids (or keys) as a warning prints it: the first [`IDS_SHOWN`], then how many
/// more.
///
/// ```
/// use monitor_host::warning::id_list;
/// let ids: Vec<String> = (1..=12).map(|i| i.to_string()).collect();
/// assert_eq!(id_list(&ids), "1, 2, 3, 4, 5, 6, 7, 8, 9, 10 and 2 more");
/// assert_eq!(id_list(&ids[..2]), "1, 2");
/// ```
pub fn id_list<S: AsRef<str>>(ids: &[S]) -> String {
    let shown: Vec<&str> = ids.iter().take(IDS_SHOWN).map(AsRef::as_ref).collect();
    let mut s = shown.join(", ");
    if ids.len() > IDS_SHOWN {
        s.push_str(&format!(" and {} more", ids.len() - IDS_SHOWN));
    }
    s
}

impl serde::Serialize for Warning {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

impl<'de> serde::Deserialize<'de> for Warning {
    /// A report's warning reads back as its text ([`Warning::Recorded`]).
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        <String as serde::Deserialize>::deserialize(d).map(Warning::Recorded)
    }
}
