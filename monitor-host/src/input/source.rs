//! Where a record came from ([`Source`]) and a route id found more than once ([`Duplicate`]):
//! the facts of docs/SCORE.md §14.1 that warnings name ([`crate::input::warning`]), apart from the
//! policy that decides between copies ([`crate::input::duplicates`]).

use std::path::PathBuf;

use crate::input::record::LoadedRecord;

/// How many ids a list in a warning or a note names before it says how many more there are.
pub const IDS_SHOWN: usize = 10;

/// Where a record came from: the file as it was found (the input argument, or the argument
/// joined with the path inside a directory) and its index in that file.
#[derive(Clone, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
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
