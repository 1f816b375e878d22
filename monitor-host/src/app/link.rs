//! `sds link` and `sds.link`: play a run (or vehicle logs) to a checker over a byte stream and
//! report, per route, whether its events equal the replay of the frames it accepted
//! (docs/SCORE.md, "Live link"). The front ends fill a [`LinkRequest`] and call
//! [`LinkRequest::run`].

use std::path::PathBuf;

use crate::app::run::{named_frames, Inputs};
use crate::app::score::{log_topics, RequestError};
use crate::live_link::doer::{Pace, PlayError, Player, RouteLink};
use crate::live_link::inject::Inject;
use crate::live_link::transport::{Target, TargetError};
use crate::settings::RunSettings;
use crate::settings::SettingsError;
use monitor_core::link::LinkConfig;

/// One run to play to a checker.
#[derive(Clone, Debug)]
pub struct LinkRequest {
    /// The run's files (as `sds score`), unless `mcap` is given.
    pub inputs: Inputs,
    /// Vehicle logs instead (each one route).
    pub mcap: Vec<PathBuf>,
    /// The logs' topics, as `--topic NAME=TOPIC` gives them (refused without a log).
    pub topics: Vec<String>,
    /// The options of a scored run (profile, `--set`). Its `link.*` overrides are the
    /// checker's link settings ([`link_config`]); the doer judges acceptance with the same.
    pub settings: RunSettings,
    /// Where the checker is.
    pub target: Target,
    /// How fast.
    pub pace: Pace,
    /// Faults to inject.
    pub inject: Inject,
    /// Where to copy the bytes sent and received (`sent.bin`, `received.bin`).
    pub tap: Option<PathBuf>,
}

/// A route that could not be played (its frames could not be made).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Unplayed {
    /// The route id, or the source.
    pub route_id: String,
    /// Why.
    pub error: String,
}

/// The summary of a played run.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct LinkRunSummary {
    /// Routes played.
    pub routes: usize,
    /// Routes whose events and summary equalled the replay's.
    pub equal_routes: usize,
    /// The target.
    pub to: String,
    /// The pace.
    pub pace: Pace,
    /// The faults injected.
    pub inject: Inject,
}

/// The report of `sds link`.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct LinkReport {
    /// Each route played, in input order.
    pub routes: Vec<RouteLink>,
    /// Routes whose frames could not be made.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub unplayed: Vec<Unplayed>,
    /// The summary.
    pub summary: LinkRunSummary,
}

impl LinkReport {
    /// Every route played was equal, and none was left unplayed (`sds link` exits 0, else 3).
    pub fn all_equal(&self) -> bool {
        self.unplayed.is_empty() && self.summary.equal_routes == self.summary.routes
    }
}

/// Why a link run stopped.
#[derive(Debug, thiserror::Error)]
pub enum LinkError {
    /// The settings.
    #[error(transparent)]
    Settings(#[from] crate::settings::SettingsError),
    /// The inputs.
    #[error(transparent)]
    Run(#[from] crate::error::Error),
    /// The request itself (topics without a log).
    #[error(transparent)]
    Request(#[from] RequestError),
    /// The target.
    #[error(transparent)]
    Target(#[from] TargetError),
    /// Playing.
    #[error(transparent)]
    Play(#[from] PlayError),
    /// The tap folder.
    #[error("--tap: {0}")]
    Tap(#[source] std::io::Error),
}

/// The link settings named `link.*` among `overrides` (`link.max_delta`, `link.timeout` in
/// frame periods, `link.window`, `link.max_errors`; docs/SCORE.md, "Live link"), validated,
/// and the other overrides in order. `sds link`, `sds checker` and Python's `sds.link` read
/// them here.
///
/// ```
/// use monitor_host::app::link::link_config;
/// let pairs = vec![("link.max_delta".to_string(), "1".to_string()), ("slack".into(), "0.9".into())];
/// let (link, rest) = link_config(&pairs).unwrap();
/// assert_eq!(link.max_delta, 1);
/// assert_eq!(rest, vec![("slack".to_string(), "0.9".to_string())]);
/// assert!(link_config(&[("link.window".into(), "40".into())]).unwrap_err().to_string().contains("1..=32"));
/// ```
///
/// # Errors
/// [`SettingsError::Value`] naming the setting, the value given and what it takes.
pub fn link_config(
    overrides: &[(String, String)],
) -> Result<(LinkConfig, Vec<(String, String)>), SettingsError> {
    let mut link = LinkConfig::DEFAULT;
    let mut rest = Vec::new();
    for (name, value) in overrides {
        let bad = |expected: &str| SettingsError::Value {
            name: "--set",
            expected: expected.into(),
            value: format!("{name}={value}"),
        };
        let v = value.trim();
        match name.trim() {
            "link.max_delta" => {
                link.max_delta = v.parse().map_err(|_| bad("link.max_delta=N, 1..=65535"))?
            }
            "link.timeout" => {
                link.timeout = v
                    .parse()
                    .map_err(|_| bad("link.timeout=N frame periods, 1..=65535"))?
            }
            "link.window" => link.window = v.parse().map_err(|_| bad("link.window=N, 1..=32"))?,
            "link.max_errors" => {
                link.max_errors = v
                    .parse()
                    .map_err(|_| bad("link.max_errors=N, below link.window"))?
            }
            other if other.starts_with("link.") => {
                return Err(bad(
                    "link.max_delta, link.timeout, link.window or link.max_errors",
                ))
            }
            _ => rest.push((name.clone(), value.clone())),
        }
    }
    link.validate().map_err(|e| SettingsError::Value {
        name: "--set",
        expected: e.to_string(),
        value: overrides
            .iter()
            .filter(|(n, _)| n.trim().starts_with("link."))
            .map(|(n, v)| format!("{n}={v}"))
            .collect::<Vec<_>>()
            .join(" "),
    })?;
    Ok((link, rest))
}

impl LinkRequest {
    /// Plays every route and compares.
    ///
    /// # Errors
    /// [`LinkError`].
    pub fn run(&self) -> Result<LinkReport, LinkError> {
        // Refused before the checker is contacted, as `ScoreRequest::validate` refuses both.
        if !self.mcap.is_empty() && !self.inputs.results.is_empty() {
            return Err(RequestError::Log(
                "results and vehicle logs (--mcap) are played apart: give one or the other".into(),
            )
            .into());
        }
        let topics = log_topics(!self.mcap.is_empty(), &self.topics)?;
        // The link settings are the checker's, not the monitor's.
        let (link, overrides) = link_config(&self.settings.overrides)?;
        let settings = RunSettings {
            overrides,
            ..self.settings.clone()
        }
        .settings()?;
        let mut routes: Vec<(String, Result<crate::model::frames::RouteFrames, String>)> =
            Vec::new();
        if self.mcap.is_empty() {
            for (id, (_, frames)) in named_frames(&self.inputs, &settings)? {
                routes.push((id, frames.map_err(|e| crate::error::message(&e))));
            }
        } else {
            for log in &self.mcap {
                let frames = crate::app::run::vehicle_logs::log_frames(log, &topics, &settings)
                    .map_err(|e| crate::error::message(&e));
                routes.push((crate::input::mcap::log_name(log), frames));
            }
        }
        let conn = self.target.connect()?;
        let mut player = Player::new(conn, self.pace, self.inject, link, self.tap.as_deref())
            .map_err(LinkError::Tap)?;
        let mut played = Vec::new();
        let mut unplayed = Vec::new();
        for (id, frames) in routes {
            match frames {
                Ok(rf) => {
                    let config = monitor_core::Config {
                        dt: rf.dt,
                        ..settings.core
                    };
                    played.push(player.play(&id, config, &rf.frames)?);
                }
                Err(error) => unplayed.push(Unplayed {
                    route_id: id,
                    error,
                }),
            }
        }
        player.close();
        let equal = played.iter().filter(|r| r.link.equal).count();
        Ok(LinkReport {
            summary: LinkRunSummary {
                routes: played.len(),
                equal_routes: equal,
                to: self.target.to_string(),
                pace: self.pace,
                inject: self.inject,
            },
            routes: played,
            unplayed,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Results and logs together are refused before the checker is contacted (the target is a
    /// command that would fail if it were run).
    #[test]
    fn results_and_logs_are_refused_before_any_connection() {
        let request = LinkRequest {
            inputs: Inputs::new(["results.json"]),
            mcap: vec!["drive.mcap".into()],
            topics: Vec::new(),
            settings: RunSettings::default(),
            target: "exec:false".parse().unwrap(),
            pace: Pace::Fast,
            inject: Inject::default(),
            tap: None,
        };
        match request.run() {
            Err(LinkError::Request(RequestError::Log(m))) => assert!(m.contains("apart"), "{m}"),
            other => panic!("expected the request refused, got {other:?}"),
        }
    }
}
