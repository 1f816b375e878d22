//! `sds frames` and `sds.frames`: the monitor's input frames of one route, or of one vehicle
//! log, as the replay streams them ([`FramesRequest`]). Each front end fills the request from
//! its own spelling; the settings, the checks and the reading are here, once.

use std::path::PathBuf;

use crate::app::run::vehicle_logs::log_frames;
use crate::app::run::{route_frames, Inputs};
use crate::app::score::{log_topics, RequestError, ScoreError};
use crate::model::frames::RouteFrames;
use crate::settings::RunSettings;
use crate::settings::Settings;

/// The frames of one route (`sds frames`, `sds.frames`): a route of a run by its id, or a
/// vehicle log (docs/SCORE.md, "Vehicle logs").
///
/// ```
/// use monitor_host::app::frames::FramesRequest;
/// use monitor_host::{demo, Inputs};
///
/// let dir = tempfile::tempdir()?;
/// let run = demo::write(dir.path())?;
/// let request = FramesRequest {
///     route_id: Some(run.route_ids[0].clone()),
///     ..FramesRequest::new(Inputs { telemetry: Some(run.telemetry), ..Inputs::new([run.results]) })
/// };
/// let frames = request.frames()?;
/// assert_eq!(frames.route_id, run.route_ids[0]);
/// assert!(!frames.frames.frames.is_empty());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FramesRequest {
    /// The run's files (no results with a log).
    pub inputs: Inputs,
    /// The options that change a frame (the profile, the duplicate rule, the settings).
    pub settings: RunSettings,
    /// The route (`RouteScenario_<id>_rep<k>`); none with a log.
    pub route_id: Option<String>,
    /// A vehicle log (an MCAP file or a rosbag2 folder) instead of a run's route.
    pub log: Option<PathBuf>,
    /// The log's topics, `NAME=TOPIC` each.
    pub topics: Vec<String>,
}

/// The frames of a [`FramesRequest`] and the name of their route (the log's name for a log).
#[derive(Debug)]
pub struct Frames {
    /// The route id, or the log's name.
    pub route_id: String,
    /// The frames, with the warnings met while reading them.
    pub frames: RouteFrames,
}

impl FramesRequest {
    /// A request for `inputs` with the default options (its `route_id` still to name).
    pub fn new(inputs: Inputs) -> Self {
        FramesRequest {
            inputs,
            ..FramesRequest::default()
        }
    }

    /// Checks the request before any work; returns its settings.
    ///
    /// # Errors
    /// [`RequestError::Settings`]; [`RequestError::Log`]: topics without a log, a log with
    /// results.
    pub fn validate(&self) -> Result<Settings, RequestError> {
        let settings = self.settings.settings()?;
        if self.log.is_some() && !self.inputs.results.is_empty() {
            return Err(RequestError::Log(
                "frames are read from a run's results or from one vehicle log (--mcap): give \
                 one or the other"
                    .into(),
            ));
        }
        log_topics(self.log.is_some(), &self.topics)?;
        Ok(settings)
    }

    /// Reads the frames.
    ///
    /// # Errors
    /// [`ScoreError::Request`] before any work; else the reading's [`crate::Error`] (no such
    /// route, an invalid record, telemetry or log that cannot be read).
    pub fn frames(&self) -> Result<Frames, ScoreError> {
        let settings = self.validate()?;
        Ok(match &self.log {
            Some(log) => Frames {
                frames: log_frames(log, &log_topics(true, &self.topics)?, &settings)?,
                route_id: crate::input::mcap::log_name(log),
            },
            None => {
                let id = self.route_id.clone().unwrap_or_default();
                Frames {
                    frames: route_frames(&self.inputs, &id, &settings)?,
                    route_id: id,
                }
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A front end without clap's checks (Python) gets the command line's refusals.
    #[test]
    fn topics_need_a_log_and_a_log_takes_no_results() {
        let topics = FramesRequest {
            topics: vec!["pose=/odom".into()],
            ..FramesRequest::new(Inputs::new(["r.json"]))
        };
        let e = topics.validate().unwrap_err().to_string();
        assert!(
            e.contains("--topic pose=/odom names a vehicle log's topic"),
            "{e}"
        );
        let both = FramesRequest {
            log: Some("drive.mcap".into()),
            ..FramesRequest::new(Inputs::new(["r.json"]))
        };
        assert!(matches!(both.validate(), Err(RequestError::Log(_))));
    }
}
