//! A watch of an evaluation while it runs (docs/USAGE.md §8), once for every front end:
//! [`Session`] holds the rounds ([`Watcher::round`]), the wait between them, the stop rule
//! (complete and nothing new, `once`, the timeout, a stop asked for) and the final reading after
//! a timeout or a stop (retried a few times on a half-written file). A front end supplies only
//! the wait ([`Session::next`]'s `wait`: the `sds` command sleeps and checks its signals, Python
//! releases the GIL and checks its own) and renders what each step returns.

pub mod watcher;

use std::time::{Duration, Instant};

use crate::app::run::scored::Scored;
use crate::app::score::{RequestError, ScoreRequest};
use crate::app::watch::watcher::{RoundOutcome, Watcher, RACY};
use crate::error::Error;
use crate::model::status::RoundStatus;

/// Tries of the final reading after a timeout or a stop, when it finds a file half-written.
const LAST_TRIES: usize = 5;
/// The pause between those tries.
const LAST_PAUSE: Duration = Duration::from_millis(200);

/// A watch to run (`sds watch`, `sds.watch`): the run of `sds score` and the rounds' timing.
#[derive(Clone, Debug, PartialEq)]
pub struct WatchRequest {
    /// The run, as `sds score` scores it.
    pub score: ScoreRequest,
    /// Seconds between rounds: above 0, at most [`crate::app::watch::watcher::MAX_INTERVAL`].
    pub interval: f64,
    /// Stop after this many seconds (0 to [`crate::app::watch::watcher::MAX_TIMEOUT`]), with a final reading.
    pub timeout: Option<f64>,
    /// One round, then stop.
    pub once: bool,
    /// K of the stalled-shard rule ([`crate::model::shard_stall`]): above 0; a shard is stalled
    /// after K times its median route time without a new record.
    pub stall_factor: f64,
}

impl WatchRequest {
    /// Checks the request before any round: the interval, the timeout, then the run's
    /// ([`ScoreRequest::validate`]).
    ///
    /// # Errors
    /// [`RequestError`].
    pub fn validate(&self) -> Result<(), RequestError> {
        interval(self.interval)?;
        self.timeout.map(timeout).transpose()?;
        stall_factor(self.stall_factor)?;
        no_logs(&self.score)?;
        self.score.validate()?;
        Ok(())
    }

    /// The session of the request (nothing is read until its first [`Session::next`]).
    ///
    /// ```
    /// use monitor_host::app::score::ScoreRequest;
    /// use monitor_host::app::watch::{Step, Stop, Wake, WatchRequest};
    /// use monitor_host::{demo, Inputs};
    ///
    /// let dir = tempfile::tempdir()?;
    /// let run = demo::write(dir.path())?;
    /// let score = ScoreRequest::new(Inputs { telemetry: Some(run.telemetry),
    ///                                        ..Inputs::new([run.results]) });
    /// let request = WatchRequest { score, interval: 0.01, timeout: None, once: true,
    ///                              stall_factor: 5.0 };
    /// let mut session = request.session()?;
    /// let mut wait = |_| Wake::Elapsed; // a front end sleeps here and checks its signals
    /// assert!(matches!(session.next(&mut wait)?, Step::Round { stops: Some(Stop::Once), .. }));
    /// let Step::Stopped(end) = session.next(&mut wait)? else { panic!() };
    /// assert_eq!(end.status.stopped.as_deref(), Some("once"));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    ///
    /// # Errors
    /// As [`WatchRequest::validate`].
    pub fn session(&self) -> Result<Session, RequestError> {
        let interval = interval(self.interval)?;
        let timeout = self.timeout.map(timeout).transpose()?;
        let stall_factor = stall_factor(self.stall_factor)?;
        no_logs(&self.score)?;
        let settings = self.score.validate()?;
        let s = &self.score;
        let mut watcher = Watcher::new(
            s.inputs.clone(),
            settings,
            s.labels.clone(),
            s.group_by,
            RACY,
        );
        watcher.set_stall_factor(stall_factor);
        Ok(Session {
            watcher,
            interval,
            timeout,
            once: self.once,
            start: None,
            rounds: 0,
            pending: None,
            stopped: false,
        })
    }
}

/// A watch follows results files while they are written: a vehicle log is a finished file.
fn no_logs(score: &ScoreRequest) -> Result<(), RequestError> {
    if score.logs.is_empty() {
        return Ok(());
    }
    Err(RequestError::Log(
        "sds watch follows an evaluation's results files while they are written; a vehicle log \
         (--mcap) is a finished file: score it with sds score --mcap"
            .into(),
    ))
}

/// The interval, checked.
fn interval(secs: f64) -> Result<Duration, RequestError> {
    crate::app::watch::watcher::interval(secs)
        .map_err(|bound| RequestError::Interval { given: secs, bound })
}

/// K of the stalled-shard rule, checked: a number above 0.
fn stall_factor(k: f64) -> Result<f64, RequestError> {
    if k.is_finite() && k > 0.0 {
        Ok(k)
    } else {
        Err(RequestError::StallFactor { given: k })
    }
}

/// The timeout, checked.
fn timeout(secs: f64) -> Result<Duration, RequestError> {
    crate::app::watch::watcher::timeout(secs)
        .map_err(|bound| RequestError::Timeout { given: secs, bound })
}

/// What ended a front end's wait.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Wake {
    /// The time asked for passed.
    Elapsed,
    /// A stop was asked for (Ctrl-C, SIGTERM): the watch reads the inputs once more and stops.
    Stop,
    /// The front end gives up at once (a Python exception to raise): no final reading.
    Abort,
}

/// Why a watch stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stop {
    /// The route set is complete, and a round found nothing new.
    Complete,
    /// One round was asked for.
    Once,
    /// The timeout passed.
    Timeout,
    /// A stop was asked for ([`Wake::Stop`]).
    Interrupted,
}

impl Stop {
    /// Its name in the status (`stopped`).
    pub fn name(self) -> &'static str {
        match self {
            Stop::Complete => "complete",
            Stop::Once => "once",
            Stop::Timeout => "timeout",
            Stop::Interrupted => "interrupted",
        }
    }
}

/// What one [`Session::next`] came to.
#[derive(Debug)]
#[allow(clippy::large_enum_variant)]
pub enum Step {
    /// A round while the watch runs: scored, or retried (a results file caught half-written).
    Round {
        /// The round.
        outcome: RoundOutcome,
        /// The watch stops with this round ([`Stop::Complete`], [`Stop::Once`]): the next call
        /// returns [`Step::Stopped`] at once.
        stops: Option<Stop>,
    },
    /// The watch stopped.
    Stopped(End),
    /// The front end's wait said [`Wake::Abort`].
    Aborted,
}

/// How a watch ended.
#[derive(Debug)]
pub struct End {
    /// Why.
    pub stop: Stop,
    /// After a timeout or a stop, the final reading's report and status, when it scored.
    pub reread: Option<(Box<Scored>, RoundStatus)>,
    /// The final reading found something new since the round before it.
    pub changed: bool,
    /// The final reading found a results file still half-written every time: why.
    pub stale: Option<String>,
    /// The status of the last round, `stopped` set: the last status line.
    pub status: RoundStatus,
}

/// A watch running: see the module.
#[derive(Debug)]
pub struct Session {
    watcher: Watcher,
    interval: Duration,
    timeout: Option<Duration>,
    once: bool,
    start: Option<Instant>,
    rounds: usize,
    /// The watch stops with the round returned last.
    pending: Option<Stop>,
    stopped: bool,
}

impl Session {
    /// The next step: the first call runs a round at once; each later one first waits the
    /// interval through `wait` (called with at most the time left of the interval and of the
    /// timeout, again until the interval has passed), then runs a round. The timeout counts from
    /// the first call. After a timeout or a stop the inputs are read once more (retried
    /// `LAST_TRIES` times on a half-written file) and the watch stops. Once stopped, every call
    /// returns [`Step::Aborted`].
    ///
    /// # Errors
    /// A round's error no later write of the evaluator can mend ([`Watcher::round`]).
    pub fn next(&mut self, wait: &mut dyn FnMut(Duration) -> Wake) -> Result<Step, Error> {
        if self.stopped {
            return Ok(Step::Aborted);
        }
        let start = *self.start.get_or_insert_with(Instant::now);
        if let Some(stop) = self.pending.take() {
            return Ok(Step::Stopped(self.end(stop, None, false, None)));
        }
        if self.rounds > 0 {
            let until = Instant::now() + self.interval;
            loop {
                if self.timeout.is_some_and(|t| start.elapsed() >= t) {
                    return self.final_reading(Stop::Timeout);
                }
                let now = Instant::now();
                if now >= until {
                    break;
                }
                let left = self.timeout.map_or(until - now, |t| {
                    (until - now).min(t - start.elapsed().min(t))
                });
                match wait(left) {
                    Wake::Elapsed => {}
                    Wake::Stop => return self.final_reading(Stop::Interrupted),
                    Wake::Abort => {
                        self.stopped = true;
                        return Ok(Step::Aborted);
                    }
                }
            }
        }
        self.rounds += 1;
        let outcome = self.watcher.round()?;
        let complete = matches!(
            &outcome,
            RoundOutcome::Scored { status, changed, .. } if status.complete && !changed
        );
        self.pending = if complete {
            Some(Stop::Complete)
        } else {
            self.once.then_some(Stop::Once)
        };
        Ok(Step::Round {
            outcome,
            stops: self.pending,
        })
    }

    /// The inputs read once more after a timeout or a stop (they may have changed since the
    /// last round), retried on a half-written file.
    fn final_reading(&mut self, stop: Stop) -> Result<Step, Error> {
        let mut stale = None;
        for i in 0..LAST_TRIES {
            if i > 0 {
                std::thread::sleep(LAST_PAUSE);
            }
            match self.watcher.round()? {
                RoundOutcome::Scored {
                    scored,
                    changed,
                    status,
                    ..
                } => {
                    return Ok(Step::Stopped(self.end(
                        stop,
                        Some((scored, status)),
                        changed,
                        None,
                    )))
                }
                RoundOutcome::Retry { reason, .. } => stale = Some(reason),
            }
        }
        Ok(Step::Stopped(self.end(stop, None, false, stale)))
    }

    fn end(
        &mut self,
        stop: Stop,
        reread: Option<(Box<Scored>, RoundStatus)>,
        changed: bool,
        stale: Option<String>,
    ) -> End {
        self.stopped = true;
        End {
            stop,
            reread,
            changed,
            stale,
            status: RoundStatus {
                stopped: Some(stop.name().into()),
                ..self.watcher.last_status().clone()
            },
        }
    }

    /// The watcher (its progress figures, its last status).
    pub fn watcher(&self) -> &Watcher {
        &self.watcher
    }
}
