//! What a front end asks of a scored run, typed: [`ScoreRequest`] (with [`RunSettings`], the
//! options every scored run takes) (`sds score`, `sds.score`; `sds watch` and `sds.watch` through
//! [`crate::app::watch::WatchRequest`]). Each front end fills a request from its own spelling
//! (clap's arguments, Python's keyword arguments) and calls it; the mapping to [`Settings`], the
//! checks and the calls into the library are here, once.

use std::path::PathBuf;

use crate::aggregate::groups::GroupBy;
use crate::app::run::scored::{score_labelled, LabelFiles, Scored};
use crate::app::run::vehicle_logs::score_logs;
use crate::app::run::{run_frames, Inputs, Progress};
use crate::error::Error;
use crate::input::mcap::Topics;
use crate::input::record::KNOWN_LISTS;
use crate::model::Report;
use crate::settings::{RunSettings, Settings, SettingsError};

/// Why a request is refused before any work: a usage error of the front end (the `sds` command
/// exits 2; Python raises `ConfigError`). Each front end may name its own option.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RequestError {
    /// A setting that names no setting, or whose value does not parse or validate.
    #[error(transparent)]
    Settings(#[from] SettingsError),
    /// An extra infraction list of the per-weather table that no record has: a mistyped name
    /// would add a column of zeros.
    #[error(
        "--infraction {0}: no such infraction list; the lists are {known}",
        known = KNOWN_LISTS.join(", ")
    )]
    UnknownInfraction(String),
    /// The interval between a watch's rounds out of its bounds (the value given, the bounds).
    #[error("interval {given}: {bound}")]
    Interval {
        /// The value given, s.
        given: f64,
        /// The bounds, said.
        bound: String,
    },
    /// A watch's stalled-shard factor K that is not a number above 0.
    #[error("stall factor {given}: expected a number above 0 (default {default})", default = crate::model::shard_stall::DEFAULT_FACTOR)]
    StallFactor {
        /// The value given.
        given: f64,
    },
    /// Vehicle logs and their topics that do not fit the request: a topic without a log, a
    /// signal named twice, a log where the command reads none.
    #[error("{0}")]
    Log(String),
    /// A watch's timeout out of its bounds.
    #[error("timeout {given}: {bound}")]
    Timeout {
        /// The value given, s.
        given: f64,
        /// The bounds, said.
        bound: String,
    },
}

/// One run to score (`sds score`, `sds.score`): its files, settings, label files and breakdown.
///
/// ```
/// use monitor_host::app::score::ScoreRequest;
/// use monitor_host::{demo, Inputs, NoProgress};
///
/// let dir = tempfile::tempdir()?;
/// let run = demo::write(dir.path())?;
/// let request = ScoreRequest::new(Inputs { telemetry: Some(run.telemetry),
///                                          ..Inputs::new([run.results]) });
/// let scored = request.score(&NoProgress)?;
/// assert_eq!(scored.report.routes.len(), run.route_ids.len());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ScoreRequest {
    /// The files.
    pub inputs: Inputs,
    /// The options.
    pub settings: RunSettings,
    /// The label files.
    pub labels: LabelFiles,
    /// The breakdown (the report's `groups`), if any.
    pub group_by: Option<GroupBy>,
    /// Extra infraction lists of the per-weather table (checked against the lists a record has).
    pub infractions: Vec<String>,
    /// Vehicle logs (MCAP files or rosbag2 folders) scored instead of results, each one route
    /// (docs/SCORE.md, "Vehicle logs"); `inputs.results` is then empty.
    pub logs: Vec<PathBuf>,
    /// The logs' topics, `NAME=TOPIC` each (`pose=/odom`, `imu=/imu`, `event=...`, `path=...`).
    pub topics: Vec<String>,
}

impl ScoreRequest {
    /// A request for `inputs` with the default options.
    pub fn new(inputs: Inputs) -> Self {
        ScoreRequest {
            inputs,
            ..ScoreRequest::default()
        }
    }

    /// Checks the request before any work; returns its settings.
    ///
    /// # Errors
    /// [`RequestError::Settings`], [`RequestError::UnknownInfraction`], [`RequestError::Log`].
    pub fn validate(&self) -> Result<Settings, RequestError> {
        let settings = self.settings.settings()?;
        if let Some(bad) = self
            .infractions
            .iter()
            .find(|l| !KNOWN_LISTS.contains(&l.as_str()))
        {
            return Err(RequestError::UnknownInfraction(bad.clone()));
        }
        if !self.logs.is_empty() && !self.inputs.results.is_empty() {
            return Err(RequestError::Log(
                "results and vehicle logs (--mcap) are scored apart: give one or the other".into(),
            ));
        }
        log_topics(!self.logs.is_empty(), &self.topics)?;
        Ok(settings)
    }

    /// Scores the run (with its label files), or its vehicle logs, telling
    /// `progress`.
    ///
    /// # Errors
    /// [`ScoreError::Request`] before any work, else the run's [`Error`].
    pub fn score(&self, progress: &dyn Progress) -> Result<Scored, ScoreError> {
        let settings = self.validate()?;
        if !self.logs.is_empty() {
            let topics = log_topics(true, &self.topics)?;
            let mut report = score_logs(&self.logs, &topics, &settings)?;
            crate::app::run::diagnostics::add_notes(&mut report);
            return Ok(Scored {
                report,
                families: None,
                weathers: None,
                labels: None,
            });
        }
        Ok(score_labelled(
            &self.inputs,
            &settings,
            &self.labels,
            self.group_by,
            progress,
        )?)
    }

    /// The long tables of the scored run (docs/TABLES-SCHEMA.md): `report`'s routes and events, and the
    /// frames of every route with telemetry, read again as `sds frames` reads them; each table
    /// as a file name and its bytes.
    ///
    /// # Errors
    /// As [`ScoreRequest::score`]; a table that cannot be made (its message).
    pub fn long_tables(&self, report: &Report) -> Result<Vec<(&'static str, Vec<u8>)>, ScoreError> {
        let frames: Vec<_> = run_frames(&self.inputs, &self.validate()?)?
            .into_iter()
            .filter_map(|(source, f)| Some((source, f.ok()?)))
            .collect();
        let tables =
            crate::report::long_tables::long_tables(report, &frames).map_err(ScoreError::Tables)?;
        tables.files().map_err(ScoreError::Tables)
    }

    /// Every file the run read or will read that a front end must never write over (the
    /// report's files and the label files).
    pub fn inputs_read(&self, report: &Report) -> Vec<PathBuf> {
        let mut files = report.files_read.clone();
        files.extend(self.labels.files().cloned());
        files
    }
}

/// The vehicle-log topics of `NAME=TOPIC` options (docs/SCORE.md, "Vehicle logs"): a signal
/// named twice, or one topic for two signals, is refused; so are topics without a log
/// (`has_log` false) to read them from.
///
/// # Errors
/// [`RequestError::Log`], naming the option and the fix.
pub(crate) fn log_topics(has_log: bool, specs: &[String]) -> Result<Topics, RequestError> {
    if let (false, Some(first)) = (has_log, specs.first()) {
        return Err(RequestError::Log(format!(
            "--topic {first} names a vehicle log's topic, but no log is given: add --mcap FILE, \
             or leave --topic out"
        )));
    }
    Topics::parse(specs).map_err(RequestError::Log)
}

/// Why a request could not be carried out.
#[derive(Debug, thiserror::Error)]
pub enum ScoreError {
    /// Refused before any work.
    #[error(transparent)]
    Request(#[from] RequestError),
    /// The run's error.
    #[error(transparent)]
    Run(#[from] Error),
    /// A long table could not be made.
    #[error("{0}")]
    Tables(String),
}
