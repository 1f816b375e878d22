//! Several inputs and duplicate routes (`SDS-SPEC.md` v1.2 §1.5): the records of every
//! `--results` input in input order, and the `duplicates` policy that decides which copy of a
//! route id is scored.
//!
//! ```
//! use monitor_host::input::duplicates::DuplicatePolicy;
//! assert_eq!(DuplicatePolicy::from_name("last"), Some(DuplicatePolicy::Last));
//! assert_eq!(DuplicatePolicy::default().name(), "error");
//! ```

use std::collections::HashMap;
use std::path::PathBuf;

use crate::input::record::LoadedRecord;

/// What to do when two records share a `route_id` **\[decision\]**.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DuplicatePolicy {
    /// Score nothing; name every duplicated id and the sources of each copy (default).
    #[default]
    Error,
    /// Keep the first copy in input order; list the others as dropped.
    First,
    /// Keep the last copy in input order; list the others as dropped.
    Last,
    /// Score every copy as a route of its own (spec v1.1's behaviour), with a warning.
    All,
}

impl DuplicatePolicy {
    /// Every policy, in the order of the documentation.
    pub const ALL: [DuplicatePolicy; 4] = [
        DuplicatePolicy::Error,
        DuplicatePolicy::First,
        DuplicatePolicy::Last,
        DuplicatePolicy::All,
    ];

    /// The setting's value: `error`, `first`, `last` or `all`.
    pub fn name(self) -> &'static str {
        match self {
            DuplicatePolicy::Error => "error",
            DuplicatePolicy::First => "first",
            DuplicatePolicy::Last => "last",
            DuplicatePolicy::All => "all",
        }
    }

    /// The policy of this name.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|p| p.name() == name)
    }
}

/// Where a record came from: the file as it was found (the input argument, or the argument
/// joined with the path inside a directory) and its index in that file.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Source {
    /// The results file.
    pub file: PathBuf,
    /// The record's index in it (0-based).
    pub index: usize,
}

impl Source {
    /// The source of a loaded record.
    pub fn of(r: &LoadedRecord) -> Self {
        Source {
            file: r.source.clone(),
            index: r.index,
        }
    }
}

impl std::fmt::Display for Source {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} record {}", self.file.display(), self.index)
    }
}

/// A copy of a route left out by the `first` / `last` policy.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Dropped {
    /// The route id.
    pub route_id: String,
    /// The copy left out.
    pub source: Source,
    /// The copy scored.
    pub kept: Source,
}

/// One duplicated route id and every copy of it, in input order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Duplicate {
    /// The route id.
    pub route_id: String,
    /// Every copy's source.
    pub copies: Vec<Source>,
}

impl std::fmt::Display for Duplicate {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}:", self.route_id)?;
        for (i, c) in self.copies.iter().enumerate() {
            let sep = if i == 0 { " " } else { ", " };
            write!(f, "{sep}{c}")?;
        }
        Ok(())
    }
}

/// Why the run cannot be scored under `duplicates: error`.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "{} route id(s) appear more than once in the results (the same file given twice, a merged \
     file beside its raw shards, re-runs, or two models in one folder); nothing was scored. \
     Choose which copy counts with --duplicates first|last (or all to score every copy):\n  {}",
    .0.len(),
    .0.iter().map(ToString::to_string).collect::<Vec<_>>().join("\n  ")
)]
pub struct DuplicatesError(pub Vec<Duplicate>);

/// The records to score and the copies left out.
#[derive(Clone, Debug, Default)]
pub struct Deduplicated {
    /// Records kept, in input order.
    pub records: Vec<LoadedRecord>,
    /// Copies left out (`first` / `last`), in input order of the copy left out.
    pub dropped: Vec<Dropped>,
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
            duplicates,
        });
    }
    if policy == DuplicatePolicy::Error {
        return Err(DuplicatesError(duplicates));
    }
    let mut keep = vec![true; records.len()];
    let mut dropped = Vec::new();
    for (i, r) in records.iter().enumerate() {
        let Some(id) = id_of(r) else { continue };
        let all = &copies[id];
        let kept = if policy == DuplicatePolicy::First {
            all[0]
        } else {
            all[all.len() - 1]
        };
        if kept != i {
            keep[i] = false;
            dropped.push(Dropped {
                route_id: id.to_string(),
                source: Source::of(r),
                kept: Source::of(&records[kept]),
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
        duplicates,
    })
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
    fn policies() {
        let rs = vec![rec("a", 0, "R1"), rec("a", 1, "R2"), rec("b", 0, "R1")];
        let e = deduplicate(rs.clone(), DuplicatePolicy::Error).unwrap_err();
        assert_eq!(e.0.len(), 1);
        let msg = e.to_string();
        assert!(msg.contains("R1: a record 0, b record 0"), "{msg}");
        assert!(msg.contains("--duplicates first|last"), "{msg}");

        let d = deduplicate(rs.clone(), DuplicatePolicy::First).unwrap();
        assert_eq!(d.records.len(), 2);
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

        let d = deduplicate(rs, DuplicatePolicy::All).unwrap();
        assert_eq!(
            (d.records.len(), d.dropped.len(), d.duplicates.len()),
            (3, 0, 1)
        );
    }
}
