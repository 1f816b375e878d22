//! Several inputs and duplicate routes (docs/SCORE.md §14.1): the records of every
//! `--results` input in input order, and the `duplicates` policy that decides which copy of a
//! route id is scored.
//!
//! ```
//! use monitor_host::input::duplicates::DuplicatePolicy;
//! assert_eq!(DuplicatePolicy::from_name("last"), Some(DuplicatePolicy::Last));
//! assert_eq!(DuplicatePolicy::default().name(), "error");
//! ```

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use crate::input::record::LoadedRecord;

pub use crate::input::source::{Duplicate, Source, IDS_SHOWN};

named_enum! {
    /// What to do when two records share a `route_id` **\[decision\]** (the setting's value:
    /// `error`, `first`, `last`, `newest` or `all`).
    #[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
    pub enum DuplicatePolicy {
        /// Score nothing; name every duplicated id and the sources of each copy (default).
        #[default]
        Error = "error",
        /// Keep the first copy in input order; list the others as dropped.
        First = "first",
        /// Keep the last copy in input order; list the others as dropped.
        Last = "last",
        /// Keep the copy whose `save_name` time stamp (`mm_dd_HH_MM_SS`) is the latest: the
        /// newest re-run. Ties and unparsable stamps are decided by input order (the last),
        /// with a warning.
        Newest = "newest",
        /// Score every copy as a route of its own (spec v1.1's behaviour), with a warning.
        All = "all",
    }
}

/// Which copy of a duplicated route was scored and why (`first`, `last`, `newest`): the
/// report's per-route `kept`.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Kept {
    /// The policy that chose.
    #[serde(deserialize_with = "policy_name")]
    pub policy: crate::named::Name,
    /// Copies of the route id found.
    pub copies: usize,
    /// The kept copy's `save_name` time stamp (`mm_dd_HH_MM_SS`), when it has one.
    pub stamp: Option<String>,
    /// Why this copy: `first in input order`, `newest save_name time stamp (...)`, ...
    pub why: String,
    /// The copy scored.
    #[serde(skip)]
    pub source: Source,
    /// Input order decided under `newest` (a tie or an unparsable stamp).
    #[serde(skip)]
    pub by_order: bool,
    /// Under `newest`, the copies' stamps lie more than half a year apart: without a year they
    /// could wrap one (a December run and its January re-run), so the files' modification times
    /// and the checkpoint's own record order decided.
    #[serde(skip)]
    pub year_wrap: bool,
}

/// The `mm_dd_HH_MM_SS` time stamp that ends a `save_name`
/// (`RouteScenario_11715_rep0_Town12_EnterActorFlow_1_18_01_27_19_06_00`), as numbers in that
/// order (no year: the evaluator writes none), or `None` when the last five fields are not a
/// date and time.
///
/// ```
/// use monitor_host::input::duplicates::save_name_stamp;
/// let s = "RouteScenario_11715_rep0_Town12_EnterActorFlow_1_18_02_11_09_15_42";
/// assert_eq!(save_name_stamp(s), Some([2, 11, 9, 15, 42]));
/// assert_eq!(save_name_stamp("RouteScenario_1_rep0_Town01_Demo_1_7"), None);
/// assert_eq!(save_name_stamp("RouteScenario_1_rep0_Town01_Demo_1_7_13_40_10_00_00"), None); // month 13
/// ```
pub fn save_name_stamp(save_name: &str) -> Option<[u32; 5]> {
    let fields: Vec<&str> = save_name.rsplitn(6, '_').take(5).collect();
    if fields.len() < 5 {
        return None;
    }
    let mut stamp = [0u32; 5];
    for (i, f) in fields.iter().rev().enumerate() {
        if f.is_empty() || f.len() > 2 || !f.bytes().all(|b| b.is_ascii_digit()) {
            return None;
        }
        stamp[i] = f.parse().ok()?;
    }
    let [mo, d, h, mi, se] = stamp;
    ((1..=12).contains(&mo) && (1..=31).contains(&d) && h < 24 && mi < 60 && se <= 60)
        .then_some(stamp)
}

/// A stamp as written in the `save_name`.
pub(crate) fn stamp_text(s: [u32; 5]) -> String {
    s.map(|x| format!("{x:02}")).join("_")
}

/// Seconds from January 1st 00:00 of a stamp, in a year of 365 days (the stamp has no year).
fn seconds_in_year(s: [u32; 5]) -> u64 {
    const BEFORE: [u32; 12] = [0, 31, 59, 90, 120, 151, 181, 212, 243, 273, 304, 334];
    let [mo, d, h, mi, se] = s.map(u64::from);
    let days = u64::from(BEFORE[(mo as usize).clamp(1, 12) - 1]) + d.saturating_sub(1);
    ((days * 24 + h) * 60 + mi) * 60 + se
}

/// Half a year, s: stamps farther apart than this could belong to two years.
const HALF_YEAR: u64 = 183 * 86_400;

/// Whether stamps without a year could wrap one **\[decision\]**: the earliest and the latest
/// lie more than half a year apart (`12_20_...` and `01_05_...` are 16 days apart across New
/// Year, or 349 days apart within one year; runs are rarely half a year apart, re-runs after New
/// Year are common). Their order by stamp is then not trusted.
///
/// ```
/// use monitor_host::input::duplicates::stamps_could_wrap_a_year;
/// assert!(stamps_could_wrap_a_year(&[[12, 20, 10, 0, 0], [1, 5, 9, 0, 0]]));
/// assert!(!stamps_could_wrap_a_year(&[[1, 5, 9, 0, 0], [2, 11, 9, 0, 0]]));
/// ```
pub fn stamps_could_wrap_a_year(stamps: &[[u32; 5]]) -> bool {
    let t = stamps.iter().map(|&s| seconds_in_year(s));
    let (lo, hi) = t.fold((u64::MAX, 0), |(lo, hi), x| (lo.min(x), hi.max(x)));
    hi > lo && hi - lo > HALF_YEAR
}

name_field!(policy_name, DuplicatePolicy::NAMES);

/// A copy of a route left out by the `first` / `last` / `newest` policy.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Dropped {
    /// The route id.
    pub route_id: String,
    /// The copy left out.
    pub source: Source,
    /// The copy scored.
    pub kept: Source,
}

/// A results file that holds (nearly) every route id of the run: with another such file, the
/// inputs are most likely several runs (two models, two settings), not re-runs.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct WholeRun {
    /// The file.
    pub file: PathBuf,
    /// Distinct route ids in it.
    pub routes: usize,
}

/// A file is a whole run when it holds at least this share of the run's route ids...
const WHOLE_SHARE: f64 = 0.9;
/// ... and at least this many (a re-run file of one route is not a run).
const WHOLE_MIN: usize = 10;

/// Why the run cannot be scored under `duplicates: error`: every duplicated id, and the files
/// that each hold (nearly) the whole route set when there are several.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DuplicatesError {
    /// Every duplicated id with its copies.
    pub duplicates: Vec<Duplicate>,
    /// Files that each hold (nearly) every route id, when two or more do (else empty).
    pub whole_runs: Vec<WholeRun>,
    /// Distinct route ids in all inputs.
    pub ids: usize,
}

impl std::fmt::Display for DuplicatesError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.whole_runs.is_empty() {
            return write!(
                f,
                "{} route id(s) appear more than once in the results (the same file given \
                 twice, a merged file beside its raw shards, re-runs, or two models in one \
                 folder); nothing was scored. Choose which copy counts with duplicates = \
                 newest|first|last (or all to score every copy):\n  {}",
                self.duplicates.len(),
                self.duplicates
                    .iter()
                    .map(ToString::to_string)
                    .collect::<Vec<_>>()
                    .join("\n  ")
            );
        }
        let n = self.whole_runs.len();
        let all = self.whole_runs.iter().all(|w| w.routes == self.ids);
        write!(
            f,
            "{n} files each hold {} {} routes: several runs? Nothing was scored: score each \
             run on its own, or compare them side by side; duplicates would pick one copy per \
             route and mix the runs.",
            if all { "all" } else { "nearly all" },
            self.ids
        )?;
        for w in &self.whole_runs {
            write!(
                f,
                "\n  {}: {} of {} route ids",
                w.file.display(),
                w.routes,
                self.ids
            )?;
        }
        // Ids duplicated outside those files (re-runs, shards): named, the first 10.
        let other: Vec<&Duplicate> = self
            .duplicates
            .iter()
            .filter(|d| {
                d.copies
                    .iter()
                    .filter(|c| !self.whole_runs.iter().any(|w| w.file == c.file))
                    .count()
                    > 0
            })
            .collect();
        if !other.is_empty() {
            write!(
                f,
                "\n  {} route id(s) also have copies in other files:",
                other.len()
            )?;
            for d in other.iter().take(IDS_SHOWN) {
                write!(f, "\n    {d}")?;
            }
            if other.len() > IDS_SHOWN {
                write!(f, "\n    ... and {} more", other.len() - IDS_SHOWN)?;
            }
        }
        Ok(())
    }
}

impl std::error::Error for DuplicatesError {}

/// The files that each hold (nearly) every one of the `ids` distinct route ids, when two or
/// more do.
fn whole_runs(records: &[LoadedRecord], ids: usize) -> Vec<WholeRun> {
    let mut per_file: Vec<(&Path, std::collections::HashSet<&str>)> = Vec::new();
    for r in records {
        let Some(id) = id_of(r) else { continue };
        match per_file.iter_mut().find(|(f, _)| *f == r.source.as_path()) {
            Some((_, set)) => {
                set.insert(id);
            }
            None => per_file.push((&r.source, [id].into_iter().collect())),
        }
    }
    let whole: Vec<WholeRun> = per_file
        .into_iter()
        .filter(|(_, set)| set.len() >= WHOLE_MIN && set.len() as f64 >= WHOLE_SHARE * ids as f64)
        .map(|(f, set)| WholeRun {
            file: f.to_path_buf(),
            routes: set.len(),
        })
        .collect();
    if whole.len() >= 2 {
        whole
    } else {
        Vec::new()
    }
}

/// The records to score and the copies left out.
#[derive(Clone, Debug, Default)]
pub struct Deduplicated {
    /// Records kept, in input order.
    pub records: Vec<LoadedRecord>,
    /// Copies left out (`first` / `last` / `newest`), in input order of the copy left out.
    pub dropped: Vec<Dropped>,
    /// Per duplicated route id, the copy kept and why (`first` / `last` / `newest`).
    pub kept: Vec<Kept>,
    /// Duplicated ids (filled under every policy; under `all` they are all scored).
    pub duplicates: Vec<Duplicate>,
}

/// The route id of a record, valid or not (`None` when it has none).
fn id_of(r: &LoadedRecord) -> Option<&str> {
    match &r.entry {
        Ok(rec) => Some(rec.route_id.as_str()),
        Err(e) => e.route_id.as_deref(),
    }
}

/// Applies the policy to the records of every input (in input order).
///
/// # Errors
/// [`DuplicatesError`] under [`DuplicatePolicy::Error`] when some route id appears twice.
pub fn deduplicate(
    records: Vec<LoadedRecord>,
    policy: DuplicatePolicy,
) -> Result<Deduplicated, DuplicatesError> {
    let mut copies: HashMap<&str, Vec<usize>> = HashMap::new();
    let mut order: Vec<&str> = Vec::new();
    for (i, r) in records.iter().enumerate() {
        if let Some(id) = id_of(r) {
            let e = copies.entry(id).or_default();
            if e.is_empty() {
                order.push(id);
            }
            e.push(i);
        }
    }
    let duplicates: Vec<Duplicate> = order
        .iter()
        .filter(|id| copies[**id].len() > 1)
        .map(|id| Duplicate {
            route_id: (*id).to_string(),
            copies: copies[*id]
                .iter()
                .map(|&i| Source::of(&records[i]))
                .collect(),
        })
        .collect();
    if duplicates.is_empty() || policy == DuplicatePolicy::All {
        return Ok(Deduplicated {
            records,
            dropped: Vec::new(),
            kept: Vec::new(),
            duplicates,
        });
    }
    if policy == DuplicatePolicy::Error {
        return Err(DuplicatesError {
            whole_runs: whole_runs(&records, order.len()),
            ids: order.len(),
            duplicates,
        });
    }
    let mut keep = vec![true; records.len()];
    let mut dropped = Vec::new();
    let mut kept_of: HashMap<&str, usize> = HashMap::new();
    let mut kept = Vec::new();
    for d in &duplicates {
        let all = &copies[d.route_id.as_str()];
        let (index, stamp, why, by_order) = choose(&records, all, policy);
        kept_of.insert(d.route_id.as_str(), index);
        kept.push(Kept {
            policy: policy.name(),
            copies: all.len(),
            stamp: stamp.map(stamp_text),
            why: why.text,
            source: Source::of(&records[index]),
            by_order,
            year_wrap: why.year_wrap,
        });
    }
    for (i, r) in records.iter().enumerate() {
        let Some(&k) = id_of(r).and_then(|id| kept_of.get(id)) else {
            continue;
        };
        if k != i {
            keep[i] = false;
            dropped.push(Dropped {
                route_id: id_of(r).unwrap_or_default().to_string(),
                source: Source::of(r),
                kept: Source::of(&records[k]),
            });
        }
    }
    let records = records
        .into_iter()
        .zip(keep)
        .filter_map(|(r, k)| k.then_some(r))
        .collect();
    Ok(Deduplicated {
        records,
        dropped,
        kept,
        duplicates,
    })
}

/// Why a copy was kept: the report's text, and whether the stamps could wrap a year.
struct Why {
    text: String,
    year_wrap: bool,
}

impl From<String> for Why {
    fn from(text: String) -> Self {
        Why {
            text,
            year_wrap: false,
        }
    }
}

/// The file's modification time (`None` when the system cannot say).
fn modified(path: &Path) -> Option<std::time::SystemTime> {
    std::fs::metadata(path).and_then(|m| m.modified()).ok()
}

/// Under `newest`, copies whose stamps could wrap a year ([`stamps_could_wrap_a_year`]): the
/// copy of the most recently modified file, and among copies of one file (or of files modified
/// at the same time) the last in input order, which is the checkpoint's own record order within
/// a file. Without a modification time for every file, input order alone.
fn newest_by_file_time(records: &[LoadedRecord], all: &[usize], stamps: &[String]) -> (usize, Why) {
    let times: Option<Vec<std::time::SystemTime>> =
        all.iter().map(|&i| modified(&records[i].source)).collect();
    let n = all.len();
    let (pos, how) = match &times {
        Some(t) => {
            let pos = (0..n).max_by_key(|&j| (t[j], j)).unwrap_or(n - 1);
            let same_file = all
                .iter()
                .filter(|&&i| records[i].source == records[all[pos]].source)
                .count()
                > 1;
            let how = if same_file && t.iter().all(|x| *x == t[pos]) {
                format!(
                    "the last record of {} in the checkpoint's own order",
                    records[all[pos]].source.display()
                )
            } else {
                format!(
                    "the copy in the most recently modified file, {}",
                    records[all[pos]].source.display()
                )
            };
            (pos, how)
        }
        None => (
            n - 1,
            "the last copy in input order (a file's modification time is unknown)".into(),
        ),
    };
    let text = format!(
        "save_name time stamps {} lie more than half a year apart and carry no year, so they \
         could wrap one (a December run and a January re-run): kept {how}",
        stamps.join(", ")
    );
    (
        all[pos],
        Why {
            text,
            year_wrap: true,
        },
    )
}

/// Routes whose kept record comes from an earlier attempt ([`earlier_attempts`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct EarlierAttempt {
    /// The newer file: its copies were kept over `earlier`'s, and it did not finish.
    pub newer: PathBuf,
    /// Its `progress` `[done, total]` (a file without one is not known to be unfinished).
    pub progress: (u64, u64),
    /// The file the records come from.
    pub earlier: PathBuf,
    /// The records (sources) kept from `earlier` that `newer` has no copy of, with their ids.
    pub routes: Vec<(String, Source)>,
}

/// Under `newest` or `last`, the records kept from a file that a newer, unfinished file re-ran:
/// when the copies of file G were kept over those of file F (G is the re-run) and G did not
/// finish (its `progress` is `[done, total]` with `done < total`, or it holds fewer records than
/// `total`), every record of F whose route G has no copy of is from the earlier attempt: the
/// re-run crashed or stopped before reaching it. `files`: the inputs' files with their
/// `progress` ([`crate::input::results_file::InputFile`]).
pub fn earlier_attempts(
    kept: &Deduplicated,
    files: &[crate::input::results_file::InputFile],
) -> Vec<EarlierAttempt> {
    let mut pairs: Vec<(&Path, &Path)> = Vec::new();
    for d in &kept.dropped {
        let pair = (d.source.file.as_path(), d.kept.file.as_path());
        if pair.0 != pair.1 && !pairs.contains(&pair) {
            pairs.push(pair);
        }
    }
    let unfinished = |path: &Path| {
        files.iter().find(|f| f.path == path).and_then(|f| {
            f.progress
                .filter(|&(done, total)| done < total || (f.records as u64) < total)
        })
    };
    let duplicated: std::collections::HashSet<&str> = kept
        .duplicates
        .iter()
        .map(|d| d.route_id.as_str())
        .collect();
    let mut out = Vec::new();
    for (earlier, newer) in pairs {
        let Some(progress) = unfinished(newer) else {
            continue;
        };
        let routes: Vec<(String, Source)> = kept
            .records
            .iter()
            .filter(|r| r.source == earlier)
            .filter_map(|r| id_of(r).map(|id| (id, r)))
            .filter(|(id, _)| !duplicated.contains(id))
            .map(|(id, r)| (id.to_string(), Source::of(r)))
            .collect();
        if !routes.is_empty() {
            out.push(EarlierAttempt {
                newer: newer.to_path_buf(),
                progress,
                earlier: earlier.to_path_buf(),
                routes,
            });
        }
    }
    out
}

/// What `newest` decides from the copies' stamps alone.
pub(crate) enum Newest {
    /// The copy at `pos` (among the copies, in input order), why, and whether input order
    /// decided (a tie, or a copy without a stamp).
    Chosen {
        /// The copy kept.
        pos: usize,
        /// The report's text.
        why: String,
        /// Input order decided.
        by_order: bool,
    },
    /// The stamps (as written) lie more than half a year apart: they could wrap a year, and
    /// something else must decide.
    CouldWrap(Vec<String>),
}

/// `newest` over the stamps of one route id's copies, in input order: the newest stamp (the
/// last copy in input order among those that share it); the last copy when one has no stamp.
pub(crate) fn newest_of(stamps: &[Option<[u32; 5]>]) -> Newest {
    let n = stamps.len();
    if stamps.iter().any(Option::is_none) {
        let bad = stamps.iter().filter(|s| s.is_none()).count();
        return Newest::Chosen {
            pos: n - 1,
            why: format!(
                "last of {n} copies in input order: {bad} of them have no save_name time stamp \
                 (mm_dd_HH_MM_SS) to compare"
            ),
            by_order: true,
        };
    }
    let known: Vec<[u32; 5]> = stamps.iter().flatten().copied().collect();
    if stamps_could_wrap_a_year(&known) {
        return Newest::CouldWrap(known.iter().map(|s| stamp_text(*s)).collect());
    }
    let newest = stamps.iter().flatten().max().copied();
    let tied = stamps.iter().filter(|s| **s == newest).count();
    // The last copy in input order among those with the newest stamp.
    let pos = stamps.iter().rposition(|s| *s == newest).unwrap_or(n - 1);
    let others: Vec<String> = stamps
        .iter()
        .enumerate()
        .filter(|(j, _)| *j != pos)
        .filter_map(|(_, s)| s.map(stamp_text))
        .collect();
    let text = newest.map(stamp_text).unwrap_or_default();
    if tied > 1 {
        Newest::Chosen {
            pos,
            why: format!(
                "{tied} of {n} copies share the newest save_name time stamp {text}: the last of \
                 them in input order"
            ),
            by_order: true,
        }
    } else {
        Newest::Chosen {
            pos,
            why: format!(
                "newest save_name time stamp {text} of {n} copies (others {})",
                others.join(", ")
            ),
            by_order: false,
        }
    }
}

/// A stamp as a report writes it (`02_11_09_15_42`), read back.
pub(crate) fn parse_stamp(text: &str) -> Option<[u32; 5]> {
    (text.split('_').count() == 5)
        .then(|| save_name_stamp(&format!("_{text}")))
        .flatten()
}

/// The copy of one route id (indices `all`, in input order) a policy keeps: its index, its
/// stamp, why, and whether input order decided under `newest`.
fn choose(
    records: &[LoadedRecord],
    all: &[usize],
    policy: DuplicatePolicy,
) -> (usize, Option<[u32; 5]>, Why, bool) {
    let stamp_of = |i: usize| {
        records[i]
            .entry
            .as_ref()
            .ok()
            .and_then(|r| r.save_name.as_deref())
            .and_then(save_name_stamp)
    };
    let n = all.len();
    let last = all[n - 1];
    match policy {
        DuplicatePolicy::First => (
            all[0],
            stamp_of(all[0]),
            format!("first of {n} copies in input order").into(),
            false,
        ),
        DuplicatePolicy::Newest => {
            let stamps: Vec<Option<[u32; 5]>> = all.iter().map(|&i| stamp_of(i)).collect();
            match newest_of(&stamps) {
                Newest::Chosen { pos, why, by_order } => {
                    (all[pos], stamps[pos], why.into(), by_order)
                }
                Newest::CouldWrap(texts) => {
                    let (index, why) = newest_by_file_time(records, all, &texts);
                    (index, stamp_of(index), why, false)
                }
            }
        }
        _ => (
            last,
            stamp_of(last),
            format!("last of {n} copies in input order").into(),
            false,
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::record::InvalidRecord;

    fn rec(file: &str, index: usize, id: &str) -> LoadedRecord {
        LoadedRecord {
            source: file.into(),
            index,
            records_in_file: 2,
            entry: Err(InvalidRecord {
                route_id: Some(id.into()),
                reason: "test".into(),
            }),
        }
    }

    #[test]
    fn whole_runs_are_said_per_file() {
        // Two files of the same 12 routes, and a re-run of one of them.
        let mut rs: Vec<LoadedRecord> = Vec::new();
        for f in ["m1.json", "m2.json"] {
            rs.extend((0..12).map(|i| rec(f, i, &format!("R{i}"))));
        }
        rs.push(rec("rerun.json", 0, "R3"));
        let e = deduplicate(rs.clone(), DuplicatePolicy::Error).unwrap_err();
        assert_eq!(e.whole_runs.len(), 2);
        let msg = e.to_string();
        assert!(
            msg.starts_with("2 files each hold all 12 routes: several runs?"),
            "{msg}"
        );
        assert!(
            msg.contains("compare them side by side") && !msg.contains("duplicates = newest"),
            "{msg}"
        );
        assert!(msg.contains("\n  m1.json: 12 of 12 route ids"), "{msg}");
        assert!(
            msg.contains("1 route id(s) also have copies in other files:\n    R3: "),
            "{msg}"
        );
        assert!(msg.lines().count() <= 6, "{msg}");
        // One whole file and its shards: the per-id list.
        let shards: Vec<LoadedRecord> = (0..12)
            .map(|i| rec("merged.json", i, &format!("R{i}")))
            .chain((0..12).map(|i| rec(if i < 6 { "s0" } else { "s1" }, i % 6, &format!("R{i}"))))
            .collect();
        let e = deduplicate(shards, DuplicatePolicy::Error).unwrap_err();
        assert!(e.whole_runs.is_empty());
        assert_eq!(e.to_string().lines().count(), 13);
    }

    #[test]
    fn stamps() {
        let n = |s: &str| save_name_stamp(&format!("RouteScenario_11715_rep0_Town12_E_1_18_{s}"));
        assert_eq!(n("01_27_19_06_00"), Some([1, 27, 19, 6, 0]));
        assert!(n("02_07_00_00_00") > n("01_27_19_06_00"));
        assert_eq!(n("00_27_19_06_00"), None);
        assert_eq!(n("01_27_24_06_00"), None);
        assert_eq!(n("01_27_19_6x_00"), None);
        assert_eq!(save_name_stamp("19_06_00"), None);
    }

    #[test]
    fn policies() {
        let rs = vec![rec("a", 0, "R1"), rec("a", 1, "R2"), rec("b", 0, "R1")];
        let e = deduplicate(rs.clone(), DuplicatePolicy::Error).unwrap_err();
        assert_eq!(e.duplicates.len(), 1);
        assert!(e.whole_runs.is_empty());
        let msg = e.to_string();
        assert!(msg.contains("R1: a record 0, b record 0"), "{msg}");
        assert!(msg.contains("duplicates = newest|first|last"), "{msg}");

        let d = deduplicate(rs.clone(), DuplicatePolicy::First).unwrap();
        assert_eq!(d.records.len(), 2);
        assert_eq!((d.kept.len(), d.kept[0].copies), (1, 2));
        assert_eq!(d.kept[0].source, Source::of(&rs[0]));
        assert_eq!(d.records[0].source, PathBuf::from("a"));
        assert_eq!(d.dropped[0].source.file, PathBuf::from("b"));
        assert_eq!(d.dropped[0].kept.file, PathBuf::from("a"));

        let d = deduplicate(rs.clone(), DuplicatePolicy::Last).unwrap();
        let kept: Vec<_> = d.records.iter().map(|r| r.source.clone()).collect();
        assert_eq!(kept, [PathBuf::from("a"), PathBuf::from("b")]);
        assert_eq!(
            d.records[0].index, 1,
            "R2 kept; R1 from b kept, in input order"
        );
        assert_eq!(d.dropped[0].source, Source::of(&rs[0]));

        let d = deduplicate(rs.clone(), DuplicatePolicy::All).unwrap();
        assert!(d.kept.is_empty());
        assert_eq!(
            (d.records.len(), d.dropped.len(), d.duplicates.len()),
            (3, 0, 1)
        );
        // newest without readable stamps (these test records are invalid): input order
        let d = deduplicate(rs, DuplicatePolicy::Newest).unwrap();
        assert_eq!(d.dropped[0].source.file, PathBuf::from("a"));
        assert!(d.kept[0].by_order && d.kept[0].why.contains("no save_name time stamp"));
    }
}
