//! Shards that stopped progressing (docs/SCORE.md §13.2, `sds watch` over several shard
//! checkpoints): a shard whose checkpoint has had no new record for longer than K times its
//! median route time has likely lost its worker (a dead GPU, a hung CARLA server), which
//! nobody notices for hours otherwise.
//!
//! The evaluator rewrites a shard's checkpoint after every route, so the file's modification
//! time is the time of its last record, also for a shard that died before the watch started.
//! A shard's route time is the median `meta.duration_system` of its records (the median of all
//! shards' records when it has none yet). K is `sds watch --stall-factor` (default
//! [`DEFAULT_FACTOR`] **\[decision\]**: the spec names no value; five median routes without a
//! record is rare for a live worker, since routes vary about twofold around the median).
//!
//! ```
//! use monitor_host::model::shard_stall::{stalled_shards, Shard};
//! use std::time::{Duration, SystemTime};
//! let now = SystemTime::now();
//! let shard = |name: &str, idle_s: u64, done: u64| Shard {
//!     file: name.into(),
//!     done,
//!     total: 28,
//!     last_record: Some(now - Duration::from_secs(idle_s)),
//!     durations: vec![100.0, 120.0, 140.0],
//! };
//! // Median route time 120 s, K = 5: silent for 601 s is stalled, 500 s is not, a shard that
//! // is done never is.
//! let shards = [shard("eval_0.json", 500, 10), shard("eval_1.json", 601, 10),
//!               shard("eval_2.json", 9000, 28)];
//! let stalled = stalled_shards(&shards, now, 5.0);
//! assert_eq!(stalled.len(), 1);
//! assert_eq!(stalled[0].file, std::path::PathBuf::from("eval_1.json"));
//! assert_eq!(stalled[0].median_s, 120.0);
//! # assert!(stalled[0].message(5.0).contains("eval_1.json"));
//! ```

use std::path::PathBuf;
use std::time::SystemTime;

/// K's default: a shard is stalled after five of its median route times without a record.
pub const DEFAULT_FACTOR: f64 = 5.0;

/// One shard checkpoint as a watch round saw it.
#[derive(Clone, Debug, PartialEq)]
pub struct Shard {
    /// The checkpoint file.
    pub file: PathBuf,
    /// Routes done (its `progress[0]`).
    pub done: u64,
    /// Routes of the shard (its `progress[1]`).
    pub total: u64,
    /// When its last record was written (the file's modification time); `None`: unknown.
    pub last_record: Option<SystemTime>,
    /// Its records' `meta.duration_system` (s).
    pub durations: Vec<f64>,
}

/// A shard with no new record for longer than K times its median route time.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Stalled {
    /// The checkpoint file.
    pub file: PathBuf,
    /// Seconds since its last record.
    pub idle_s: f64,
    /// Its median route time (s), or all shards' when it has no record with one.
    pub median_s: f64,
    /// Routes done.
    pub done: u64,
    /// Routes of the shard.
    pub total: u64,
}

impl Stalled {
    /// The warning: the shard, how long it has been silent against K times its route time, its
    /// progress, and what to do.
    pub fn message(&self, k: f64) -> String {
        format!(
            "shard {} has written no record for {} (over {k} × its median route time {}; {}/{} \
             routes done): its worker may have died; check the node, or rerun its routes \
             (--rerun-list)",
            self.file.display(),
            crate::model::duration::duration_text(self.idle_s),
            crate::model::duration::duration_text(self.median_s),
            self.done,
            self.total
        )
    }
}

/// The shards of `now` not stalled in the previous round (`seen`, updated: a shard that wrote
/// again leaves it, so a second stall is said again): a front end warns once per stall.
pub fn newly_stalled<'a>(
    seen: &mut std::collections::HashSet<PathBuf>,
    now: &'a [Stalled],
) -> Vec<&'a Stalled> {
    seen.retain(|f| now.iter().any(|s| &s.file == f));
    now.iter().filter(|s| seen.insert(s.file.clone())).collect()
}

/// The median of finite, positive values (`None` for none).
fn median(xs: impl IntoIterator<Item = f64>) -> Option<f64> {
    let mut v: Vec<f64> = xs
        .into_iter()
        .filter(|x| x.is_finite() && *x > 0.0)
        .collect();
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let m = v.len() / 2;
    Some(if v.len() % 2 == 1 {
        v[m]
    } else {
        (v[m - 1] + v[m]) / 2.0
    })
}

/// The shards that stopped progressing at `now`, with K = `k`, in the order given. Only several
/// shard checkpoints are judged (a checkpoint of more than one route: `total > 1`); a shard
/// whose progress says done, one without a known last write, or one whose route time is
/// unknown is never stalled. A `k` that is not finite and positive judges nothing.
pub fn stalled_shards(shards: &[Shard], now: SystemTime, k: f64) -> Vec<Stalled> {
    let checkpoints: Vec<&Shard> = shards.iter().filter(|s| s.total > 1).collect();
    if checkpoints.len() < 2 || !(k.is_finite() && k > 0.0) {
        return Vec::new();
    }
    let all = median(checkpoints.iter().flat_map(|s| s.durations.iter().copied()));
    checkpoints
        .into_iter()
        .filter(|s| s.done < s.total)
        .filter_map(|s| {
            let median_s = median(s.durations.iter().copied()).or(all)?;
            let idle_s = now.duration_since(s.last_record?).ok()?.as_secs_f64();
            (idle_s > k * median_s).then(|| Stalled {
                file: s.file.clone(),
                idle_s,
                median_s,
                done: s.done,
                total: s.total,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    fn shard(file: &str, idle: u64, done: u64, durations: &[f64]) -> (Shard, SystemTime) {
        let now = SystemTime::UNIX_EPOCH + Duration::from_secs(1_000_000);
        (
            Shard {
                file: file.into(),
                done,
                total: 10,
                last_record: Some(now - Duration::from_secs(idle)),
                durations: durations.to_vec(),
            },
            now,
        )
    }

    #[test]
    fn a_shard_without_records_takes_every_shards_median() {
        let (a, now) = shard("a", 10, 3, &[60.0, 60.0, 90.0]);
        let (b, _) = shard("b", 301, 0, &[]);
        let s = stalled_shards(&[a.clone(), b.clone()], now, 5.0);
        assert_eq!(s.len(), 1);
        assert_eq!((s[0].file.to_str(), s[0].median_s), (Some("b"), 60.0));
        // A single checkpoint is not a set of shards; a bad K judges nothing.
        assert!(stalled_shards(std::slice::from_ref(&b), now, 5.0).is_empty());
        assert!(stalled_shards(&[a.clone(), b.clone()], now, f64::NAN).is_empty());
        assert!(stalled_shards(&[a, b], now, 0.0).is_empty());
    }

    #[test]
    fn unknown_times_and_future_writes_are_never_stalled() {
        let (a, now) = shard("a", 10, 3, &[]);
        let (b, _) = shard("b", 100_000, 3, &[f64::NAN, -1.0]);
        assert!(stalled_shards(&[a.clone(), b], now, 5.0).is_empty());
        let mut c = a.clone();
        c.durations = vec![1.0];
        c.last_record = Some(now + Duration::from_secs(50));
        let mut d = a;
        d.durations = vec![1.0];
        d.last_record = None;
        assert!(stalled_shards(&[c, d], now, 5.0).is_empty());
    }

    #[test]
    fn a_stall_is_said_once_until_the_shard_writes_again() {
        let st = |f: &str| Stalled {
            file: f.into(),
            idle_s: 1.0,
            median_s: 1.0,
            done: 1,
            total: 2,
        };
        let mut seen = std::collections::HashSet::new();
        assert_eq!(newly_stalled(&mut seen, &[st("a")]).len(), 1);
        assert!(newly_stalled(&mut seen, &[st("a")]).is_empty());
        assert!(newly_stalled(&mut seen, &[]).is_empty());
        assert_eq!(newly_stalled(&mut seen, &[st("a"), st("b")]).len(), 2);
    }

    #[test]
    fn the_median_is_the_middle_value() {
        assert_eq!(median([3.0, 1.0, 2.0]), Some(2.0));
        assert_eq!(median([4.0, 1.0, 2.0, 3.0]), Some(2.5));
        assert_eq!(median([]), None);
    }
}
