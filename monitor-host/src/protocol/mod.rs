//! Scoring protocols (`SDS-SPEC.md` v1.3 §8.4): the *recorded* events of every route rescored
//! under the arithmetic of other evaluators — Bench2Drive (`b2d`), CARLA Leaderboard 2.0
//! (`lb2.0`) and 2.1 (`lb2.1`), LEAD's length-normalised DS (`lead-nds`) and Fail2Drive's
//! success rule (`f2d`). Nothing is re-run: a rescored route holds the same events, counted
//! under other rules. Protocols read records only (no telemetry), so streaming and batch are
//! untouched.
//!
//! One concept per file: the fixed per-event [`terms`], the [`min_speed`] entries that count,
//! the [`outside_lanes`] factor recovered from the recorded penalty, the per-route [`route`]
//! score, the [`aggregate`]s over routes, and the Bench2Drive [`ability_rule`] versions (§8.2).
//!
//! ```
//! use monitor_host::protocol::{parse_protocols, Protocol};
//! assert_eq!(parse_protocols("lb2.1,b2d")?, [Protocol::B2d, Protocol::Lb21]);
//! assert_eq!(parse_protocols("all")?.len(), 5);
//! assert!(parse_protocols("none")?.is_empty());
//! assert!(parse_protocols("lb3").is_err());
//! # Ok::<(), String>(())
//! ```

pub mod ability_rule;
pub mod aggregate;
pub mod min_speed;
pub mod outside_lanes;
pub mod route;
pub mod terms;

/// One scoring protocol (§8.4).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Protocol {
    /// Bench2Drive's evaluator: the recorded penalty and score.
    B2d,
    /// CARLA Leaderboard 2.0 (`master`): a product of per-event factors.
    Lb20,
    /// CARLA Leaderboard 2.1 (`leaderboard-2.1`): `f_out / (1 + sum of per-event costs)`.
    Lb21,
    /// LEAD's "Normalized DS": per-event factors normalised by the driven kilometres.
    LeadNds,
    /// Fail2Drive: DS as `b2d`, its own success rule, and the harmonic mean of DS and SR.
    F2d,
}

impl Protocol {
    /// Every protocol, in the order reports and tables list them.
    pub const ALL: [Protocol; 5] = [
        Protocol::B2d,
        Protocol::Lb20,
        Protocol::Lb21,
        Protocol::LeadNds,
        Protocol::F2d,
    ];

    /// The id used on the command line and as the report's key (`lb2.1`, ...).
    pub fn id(self) -> &'static str {
        match self {
            Protocol::B2d => "b2d",
            Protocol::Lb20 => "lb2.0",
            Protocol::Lb21 => "lb2.1",
            Protocol::LeadNds => "lead-nds",
            Protocol::F2d => "f2d",
        }
    }

    /// The protocol of an id.
    pub fn from_id(id: &str) -> Option<Protocol> {
        Protocol::ALL.into_iter().find(|p| p.id() == id)
    }

    /// A name for the tables (`CARLA Leaderboard 2.1`, ...).
    pub fn title(self) -> &'static str {
        match self {
            Protocol::B2d => "Bench2Drive (recorded)",
            Protocol::Lb20 => "CARLA Leaderboard 2.0",
            Protocol::Lb21 => "CARLA Leaderboard 2.1",
            Protocol::LeadNds => "LEAD normalized DS",
            Protocol::F2d => "Fail2Drive",
        }
    }
}

/// Parses the `protocols` setting: `all`, `none` (or empty), or comma-separated ids. The result
/// is in [`Protocol::ALL`] order without repeats.
///
/// # Errors
/// The text naming the unknown id and the known ones.
pub fn parse_protocols(text: &str) -> Result<Vec<Protocol>, String> {
    let text = text.trim();
    if text == "all" {
        return Ok(Protocol::ALL.to_vec());
    }
    if text.is_empty() || text == "none" {
        return Ok(Vec::new());
    }
    let mut out = Vec::new();
    for id in text.split(',').map(str::trim) {
        let p = Protocol::from_id(id).ok_or_else(|| {
            format!(
                "unknown protocol {id:?}; known: {}, or all",
                Protocol::ALL.map(Protocol::id).join(", ")
            )
        })?;
        out.push(p);
    }
    out.sort_unstable();
    out.dedup();
    Ok(out)
}

/// The `protocols` setting as text: `none`, or the ids joined by commas.
pub fn protocols_text(protocols: &[Protocol]) -> String {
    if protocols.is_empty() {
        return "none".into();
    }
    protocols
        .iter()
        .map(|p| p.id())
        .collect::<Vec<_>>()
        .join(",")
}
