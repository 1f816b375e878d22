//! The rerun list (`docs/USAGE.md`, "Routes to run again"): the routes to run again, one per
//! line in the route XML's id form with the reason after a tab, so that a Leaderboard
//! `--routes-subset` can read the ids (`--routes-subset="$(cut -f1 rerun.tsv | paste -sd, -)"`),
//! and the route XML restricted to those routes (`--rerun-xml`), which Bench2Drive's scripts
//! take as their route file. What users did by deleting records from the results JSON by hand
//! before `RESUME=1`.
//!
//! One classification ([`record_class`], [`route_class`]) decides both the list and the watch's
//! crash figure ([`crashes`]): Bench2Drive's own resume rule, which runs a route again when its
//! status is `Failed`, `Failed - Simulation crashed` or `Failed - Agent crashed`.
//! `Failed - TickRuntime` is the route's 4,000-tick budget running out: the agent's outcome,
//! listed only on request (`timeout`).
//!
//! ```
//! use monitor_host::report::rerun_list::{record_class, unsafe_id, xml_id, RerunReason};
//! assert_eq!(record_class("Failed - Simulation crashed"), Some(RerunReason::SimulationCrashed));
//! assert_eq!(record_class("Failed - Agent couldn't be set up"), Some(RerunReason::AgentSetup));
//! assert_eq!(record_class("Failed"), Some(RerunReason::Failed));
//! assert_eq!(record_class("Failed - TickRuntime"), Some(RerunReason::Timeout));
//! assert!(!RerunReason::Timeout.is_crash());
//! assert_eq!(record_class("Failed - Agent got blocked"), None);
//! assert_eq!(xml_id("RouteScenario_24785_rep0"), "24785");
//! assert_eq!(xml_id("my_route"), "my_route");
//! assert!(unsafe_id("4,5,6").is_some() && unsafe_id("24785").is_none());
//! ```

use crate::input::warning::id_list;
use crate::model::report::Report;
use crate::pipeline::outcome::{RouteState, TelemetryState};
use crate::route::row::RouteReport;

/// Why a route is run again (the reason column of the list).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RerunReason {
    /// A member of the route set without a record.
    Missing,
    /// `Failed - Simulation crashed` (also a record left `Started`: the evaluator died during
    /// the route).
    SimulationCrashed,
    /// `Failed - Agent crashed`.
    AgentCrashed,
    /// `Failed - Agent couldn't be set up` (or `... took too long to set up`).
    AgentSetup,
    /// A bare `Failed`.
    Failed,
    /// The record, or its telemetry, is invalid.
    Invalid,
    /// `Failed - TickRuntime`: the route ran out of its tick budget; listed only on request
    /// (`--rerun-timeouts`).
    Timeout,
}

impl RerunReason {
    /// The reason as the list writes it: `missing`, `simulation-crashed`, `agent-crashed`,
    /// `agent-setup`, `failed`, `invalid` or `timeout`.
    pub fn name(self) -> &'static str {
        match self {
            RerunReason::Missing => "missing",
            RerunReason::SimulationCrashed => "simulation-crashed",
            RerunReason::AgentCrashed => "agent-crashed",
            RerunReason::AgentSetup => "agent-setup",
            RerunReason::Failed => "failed",
            RerunReason::Invalid => "invalid",
            RerunReason::Timeout => "timeout",
        }
    }

    /// A class of a record whose run broke (every class but `missing`, a route not run yet, and
    /// `timeout`, the agent's outcome): what the watch's crash figure counts.
    pub fn is_crash(self) -> bool {
        !matches!(self, RerunReason::Missing | RerunReason::Timeout)
    }
}

/// The class of a record's `status` (exact Leaderboard statuses, any case, spaces around
/// ignored); `None` for a status that is the agent's outcome (`Completed`, `Perfect`,
/// `Failed - Agent got blocked`, `Failed - Agent timed out`, ...).
pub fn record_class(status: &str) -> Option<RerunReason> {
    let s = status.trim().to_ascii_lowercase();
    Some(match s.as_str() {
        "failed - simulation crashed" | "started" => RerunReason::SimulationCrashed,
        "failed - agent crashed" => RerunReason::AgentCrashed,
        "failed - agent couldn't be set up" | "failed - agent took too long to set up" => {
            RerunReason::AgentSetup
        }
        "failed" => RerunReason::Failed,
        "failed - tickruntime" => RerunReason::Timeout,
        _ => return None,
    })
}

/// The class of one route of a report: `missing` without a record, the class of its status,
/// else `invalid` when its record or its telemetry is invalid; `None` for a route to keep (and
/// for a `foreign` one, which is not the run's).
pub fn route_class(r: &RouteReport) -> Option<RerunReason> {
    match &r.state {
        RouteState::Missing => return Some(RerunReason::Missing),
        RouteState::Foreign => return None,
        _ => {}
    }
    if let Some(c) = r.status.as_deref().and_then(record_class) {
        return Some(c);
    }
    let record_invalid = matches!(r.state, RouteState::Invalid(_)) && r.status.is_none();
    (record_invalid || matches!(r.telemetry, TelemetryState::Invalid(_)))
        .then_some(RerunReason::Invalid)
}

/// The watch's crash figure: routes with a record whose class [`RerunReason::is_crash`].
pub fn crashes(report: &Report) -> usize {
    report
        .routes
        .iter()
        .filter(|r| route_class(r).is_some_and(RerunReason::is_crash))
        .count()
}

/// `RouteScenario_<id>_rep<k>` → `<id>` (the route set's own reading of an id,
/// [`crate::input::route_set::parse_route_id`]); any other id unchanged.
pub fn xml_id(route_id: &str) -> &str {
    crate::input::route_set::parse_route_id(route_id).map_or(route_id, |(id, _)| id)
}

/// Why an id cannot go into a rerun list, or `None` when it can: the list is read as
/// `id<TAB>reason` lines and its ids joined with `,` into one `--routes-subset` argument, so a
/// control character (a tab or line break adds a line), white space (an argument of its own in
/// an unquoted recipe), a `,` (several ids), a bidirectional or invisible character (a line
/// that reads otherwise than it runs) or a leading `-` (an option) would change what is run.
pub fn unsafe_id(id: &str) -> Option<&'static str> {
    if id.is_empty() {
        return Some("an empty id");
    }
    if id.starts_with('-') {
        return Some("it starts with '-' (read as an option)");
    }
    id.chars().find_map(|c| {
        if c.is_control() {
            Some("a control character")
        } else if crate::report::escape::is_hidden(c) {
            Some("a bidirectional or invisible character")
        } else if c.is_whitespace() {
            Some("white space")
        } else if c == ',' {
            Some("a ','")
        } else {
            None
        }
    })
}

/// The routes to run again, and the ids refused.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct RerunList {
    /// One per route XML id (the first reason met), in report order.
    pub routes: Vec<(String, RerunReason)>,
    /// Ids that cannot go into a list ([`unsafe_id`]), with why; run those by hand.
    pub refused: Vec<(String, &'static str)>,
}

impl RerunList {
    /// The routes of `report` to run again, in report order, one per route XML id (the first
    /// reason met): each route of a class of [`route_class`], `timeout` only when `timeouts`.
    pub fn of(report: &Report, timeouts: bool) -> RerunList {
        let mut out = RerunList::default();
        let mut seen = std::collections::HashSet::new();
        for r in &report.routes {
            let Some(reason) = route_class(r) else {
                continue;
            };
            if reason == RerunReason::Timeout && !timeouts {
                continue;
            }
            let Some(id) = r.route_id.as_deref() else {
                continue;
            };
            let id = xml_id(id).to_string();
            if !seen.insert(id.clone()) {
                continue;
            }
            match unsafe_id(&id) {
                Some(why) => out.refused.push((id, why)),
                None => out.routes.push((id, reason)),
            }
        }
        out
    }

    /// The list as text: `<id>\t<reason>\n` per route.
    pub fn text(&self) -> String {
        self.routes
            .iter()
            .map(|(id, why)| format!("{id}\t{}\n", why.name()))
            .collect()
    }

    /// The warning for the refused ids (escaped when printed), or `None` when none was.
    pub fn refused_warning(&self) -> Option<String> {
        if self.refused.is_empty() {
            return None;
        }
        let ids: Vec<String> = self
            .refused
            .iter()
            .map(|(id, why)| format!("{id:?} ({why})"))
            .collect();
        Some(format!(
            "{} route id(s) left out of the rerun list, which a --routes-subset would misread: \
             {}; run them again by hand",
            self.refused.len(),
            id_list(&ids)
        ))
    }
}

/// The rerun list as text (`timeouts`: list the `timeout` routes too).
pub fn rerun_list(report: &Report, timeouts: bool) -> String {
    RerunList::of(report, timeouts).text()
}

/// The route XML `xml` restricted to the routes `ids` (XML ids): every byte of the input but
/// the `<route>` elements of other ids and the white space before each; so each route kept is
/// its element byte for byte, with the file's prolog, root element and comments. Also returns
/// the ids that are in no `<route>` of the file.
///
/// ```
/// use monitor_host::report::rerun_list::rerun_xml;
/// let xml = b"<routes>\n  <route id=\"1\" town=\"T\"/>\n  <route id=\"2\" town=\"T\">\n    <waypoints/>\n  </route>\n</routes>\n";
/// let (out, absent) = rerun_xml(xml, &["2".to_string(), "9".to_string()])?;
/// assert_eq!(String::from_utf8(out)?,
///            "<routes>\n  <route id=\"2\" town=\"T\">\n    <waypoints/>\n  </route>\n</routes>\n");
/// assert_eq!(absent, ["9"]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// Malformed XML, with its byte offset.
pub fn rerun_xml(xml: &[u8], ids: &[String]) -> Result<(Vec<u8>, Vec<String>), String> {
    use quick_xml::events::Event;
    let mut reader = quick_xml::Reader::from_reader(xml);
    // Byte spans of the routes to leave out, and the ids met.
    let mut cut: Vec<(usize, usize)> = Vec::new();
    let mut found = std::collections::HashSet::new();
    let mut depth = 0usize;
    // The open `<route>`: its start and whether it is kept.
    let mut open: Option<(usize, usize, bool)> = None;
    let mut buf = Vec::new();
    loop {
        let start = usize::try_from(reader.buffer_position()).unwrap_or(usize::MAX);
        let event = reader
            .read_event_into(&mut buf)
            .map_err(|e| format!("not valid XML at byte {}: {e}", reader.error_position()))?;
        let end = usize::try_from(reader.buffer_position()).unwrap_or(usize::MAX);
        match event {
            Event::Start(e) => {
                if open.is_none() && e.local_name().as_ref() == b"route" {
                    let keep = route_id(&reader, &e)?.is_some_and(|id| {
                        let k = ids.contains(&id);
                        found.insert(id);
                        k
                    });
                    open = Some((start, depth, keep));
                }
                depth += 1;
            }
            Event::Empty(e) if open.is_none() && e.local_name().as_ref() == b"route" => {
                let keep = route_id(&reader, &e)?.is_some_and(|id| {
                    let k = ids.contains(&id);
                    found.insert(id);
                    k
                });
                if !keep {
                    cut.push((start, end));
                }
            }
            Event::End(_) => {
                depth = depth.saturating_sub(1);
                if let Some((s, d, keep)) = open {
                    if d == depth {
                        if !keep {
                            cut.push((s, end));
                        }
                        open = None;
                    }
                }
            }
            Event::Eof => break,
            _ => {}
        }
        buf.clear();
    }
    let mut out = Vec::with_capacity(xml.len());
    let mut at = 0;
    for (s, e) in cut {
        // The white space before a route left out goes with it.
        let mut s = s;
        while s > at && xml[s - 1].is_ascii_whitespace() {
            s -= 1;
        }
        out.extend_from_slice(&xml[at..s]);
        at = e;
    }
    out.extend_from_slice(&xml[at..]);
    let absent = ids
        .iter()
        .filter(|id| !found.contains(*id))
        .cloned()
        .collect();
    Ok((out, absent))
}

/// The `id` attribute of a `<route>` (unescaped), if it has one.
fn route_id(
    reader: &quick_xml::Reader<&[u8]>,
    e: &quick_xml::events::BytesStart<'_>,
) -> Result<Option<String>, String> {
    for a in e.attributes() {
        let a = a.map_err(|err| err.to_string())?;
        if a.key.as_ref() == b"id" {
            return a
                .decode_and_unescape_value(reader.decoder())
                .map(|v| Some(v.into_owned()))
                .map_err(|err| err.to_string());
        }
    }
    Ok(None)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_injection_of_the_round_is_refused() {
        for id in [
            "1\n2204\tcrashed",
            "4,5,6",
            "3 --agent=/tmp/evil.py",
            "--agent=/tmp/evil.py",
            "12\u{202e}34",
            "12\u{200b}",
            "a\u{a0}b",
            "",
        ] {
            assert!(unsafe_id(id).is_some(), "{id:?}");
        }
        for id in ["1711", "route_7", "Town12.a"] {
            assert_eq!(unsafe_id(id), None, "{id:?}");
        }
    }

    #[test]
    fn a_route_xml_without_the_routes_left_out_keeps_every_other_byte() {
        let xml = "<?xml version='1.0'?>\n<!-- c -->\n<routes><route id=\"1\" town=\"A\">\n  <w/>\n</route>\n   <route id=\"2\" town=\"B\"><route-ish/></route>\n<route id=\"3\"/></routes>";
        let (out, absent) = rerun_xml(xml.as_bytes(), &["1".into(), "3".into()]).unwrap();
        assert_eq!(
            String::from_utf8(out).unwrap(),
            "<?xml version='1.0'?>\n<!-- c -->\n<routes><route id=\"1\" town=\"A\">\n  <w/>\n</route>\n<route id=\"3\"/></routes>"
        );
        assert!(absent.is_empty());
        let (out, _) = rerun_xml(xml.as_bytes(), &[]).unwrap();
        assert_eq!(
            String::from_utf8(out).unwrap(),
            "<?xml version='1.0'?>\n<!-- c -->\n<routes></routes>"
        );
        assert!(rerun_xml(b"<routes><route id=\"1\"></routes>", &[]).is_err());
    }
}
