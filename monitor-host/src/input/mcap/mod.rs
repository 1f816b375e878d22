//! Vehicle logs in MCAP with ROS 2 messages (docs/SCORE.md §2.4): one log (an `.mcap` file, or a
//! rosbag2 folder of them) is one route's telemetry, named by its file stem.
//!
//! | what | module |
//! |---|---|
//! | the file, streamed in bounded memory; cuts recovered | [`stream`] |
//! | CDR, the messages' encoding | [`cdr`] |
//! | the ROS 2 types: names, definitions checked, decoding | [`messages`] |
//! | ticks at a fixed period, zero-order hold, segments cut at gaps | [`frames`](mod@frames) |
//!
//! ```no_run
//! use monitor_host::input::mcap::{read_log, Topics};
//! let log = read_log("drive.mcap".as_ref(), &Topics::default(), 0.05, 0.25)?;
//! println!("{}: {} frames, {} events", log.name, log.telemetry.frames.len(), log.events.len());
//! # Ok::<(), monitor_host::input::mcap::McapError>(())
//! ```

pub mod cdr;
pub mod frames;
pub mod messages;
pub mod stream;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use self::frames::{MotionSample, PoseSample, Sample};
use self::messages::RosType;
use crate::input::telemetry::{Telemetry, TelemetryError};

/// The topics a log's signals are read from (`--topic NAME=TOPIC`; docs/SCORE.md §2.4 defaults).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Topics {
    /// Pose: `nav_msgs/msg/Odometry` or `geometry_msgs/msg/PoseStamped` (default `/odom`).
    pub pose: String,
    /// Acceleration and yaw rate: `sensor_msgs/msg/Imu` (default `/imu`).
    pub imu: String,
    /// Events: any message is a collision or emergency event at its time (default none).
    pub event: Option<String>,
    /// The reference path: `nav_msgs/msg/Path` (default none).
    pub path: Option<String>,
}

impl Default for Topics {
    fn default() -> Self {
        Topics {
            pose: "/odom".into(),
            imu: "/imu".into(),
            event: None,
            path: None,
        }
    }
}

impl Topics {
    /// Sets one topic from `NAME=TOPIC` (`pose`, `imu`, `event`, `path`).
    ///
    /// ```
    /// let mut t = monitor_host::input::mcap::Topics::default();
    /// t.set("pose=/localization/kinematic_state")?;
    /// t.set("event=/vehicle/collision")?;
    /// assert_eq!((t.pose.as_str(), t.event.as_deref()),
    ///            ("/localization/kinematic_state", Some("/vehicle/collision")));
    /// assert!(t.set("speed=/v").is_err());
    /// # Ok::<(), String>(())
    /// ```
    ///
    /// # Errors
    /// A sentence naming the accepted names, for a name that is none of them or an empty topic.
    pub fn set(&mut self, spec: &str) -> Result<(), String> {
        let (name, topic) = spec
            .split_once('=')
            .filter(|(_, t)| !t.trim().is_empty())
            .ok_or_else(|| format!("--topic {spec:?}: expected NAME=TOPIC, e.g. pose=/odom"))?;
        let topic = topic.trim().to_string();
        match name.trim() {
            "pose" => self.pose = topic,
            "imu" => self.imu = topic,
            "event" => self.event = Some(topic),
            "path" => self.path = Some(topic),
            other => {
                return Err(format!(
                    "--topic {other}=...: unknown signal {other:?}; the signals are pose, imu, \
                     event and path"
                ))
            }
        }
        Ok(())
    }
}

impl Topics {
    /// The topics of `--topic NAME=TOPIC` options, over the defaults: a signal named twice, or
    /// one topic read as two signals (`event=/imu` beside the default `imu=/imu`: every IMU
    /// message would be a collision), is refused.
    ///
    /// ```
    /// use monitor_host::input::mcap::Topics;
    /// let t = Topics::parse(&["pose=/pose".into(), "imu=/odom".into()])?;
    /// assert_eq!((t.pose.as_str(), t.imu.as_str()), ("/pose", "/odom"));
    /// assert!(Topics::parse(&["pose=/a".into(), "pose=/b".into()]).unwrap_err().contains("twice"));
    /// assert!(Topics::parse(&["event=/imu".into()]).unwrap_err().contains("both imu and event"));
    /// # Ok::<(), String>(())
    /// ```
    ///
    /// # Errors
    /// A sentence naming the option and the fix.
    pub fn parse(specs: &[String]) -> Result<Topics, String> {
        let mut topics = Topics::default();
        let mut given: Vec<(String, &String)> = Vec::new();
        for spec in specs {
            topics.set(spec)?;
            let name = spec
                .split_once('=')
                .map_or("", |(n, _)| n)
                .trim()
                .to_string();
            if let Some((_, first)) = given.iter().find(|(n, _)| *n == name) {
                return Err(format!(
                    "--topic {name}=... is given twice ({first:?}, then {spec:?}): a signal is \
                     read from one topic; give it once"
                ));
            }
            given.push((name, spec));
        }
        let signals: [(&str, Option<&String>); 4] = [
            ("pose", Some(&topics.pose)),
            ("imu", Some(&topics.imu)),
            ("event", topics.event.as_ref()),
            ("path", topics.path.as_ref()),
        ];
        for (i, (a, ta)) in signals.iter().enumerate() {
            for (b, tb) in &signals[i + 1..] {
                if let (Some(ta), Some(tb)) = (ta, tb) {
                    if ta == tb {
                        return Err(format!(
                            "--topic: {ta} would be read as both {a} and {b}; a topic is one \
                             signal: name another topic with --topic {a}=TOPIC or --topic \
                             {b}=TOPIC"
                        ));
                    }
                }
            }
        }
        Ok(topics)
    }

    /// Whether messages of `topic` are read (one of the four signals).
    pub fn reads(&self, topic: &str) -> bool {
        topic == self.pose
            || topic == self.imu
            || self.event.as_deref() == Some(topic)
            || self.path.as_deref() == Some(topic)
    }
}

/// One event of the event topic: its log time and the frame it falls on (the first frame at
/// or after it), if any.
#[derive(Debug, Clone, PartialEq)]
pub struct LogEvent {
    /// Log time, ns.
    pub t: u64,
    /// Index of the frame (into the telemetry's frames): the first at or after it within
    /// `mcap.max_hold`, else the last before it within one period; `None` when the event lies
    /// in a gap.
    pub frame: Option<usize>,
    /// The message's schema name (`std_msgs/msg/Empty`, ...).
    pub kind: String,
}

/// A vehicle log, read and framed.
#[derive(Debug, Clone, PartialEq)]
pub struct VehicleLog {
    /// The route's name: the file stem (`drive_2024_05_01.mcap` → `drive_2024_05_01`), or the
    /// rosbag2 folder's name.
    pub name: String,
    /// The file (or folder) given.
    pub path: PathBuf,
    /// The MCAP files read, in order.
    pub files: Vec<PathBuf>,
    /// The frames: step = tick index.
    pub telemetry: Telemetry,
    /// Tick time (ns) of each frame.
    pub times: Vec<u64>,
    /// The period, s.
    pub dt: f64,
    /// The events of the event topic.
    pub events: Vec<LogEvent>,
    /// The reference path (x, y, z), from the last message of the path topic.
    pub path_points: Option<Vec<[f64; 3]>>,
    /// Messages read (all topics) and bytes of the files.
    pub messages: u64,
    /// Bytes of the files.
    pub bytes: u64,
    /// What the reader noted: cuts, corrupt chunks, messages out of order, gaps, the IMU
    /// fallback. A note does not repeat the log's path (the warning names it).
    pub notes: Vec<String>,
}

/// Why a log cannot be scored. Every message names the file and says what to do.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum McapError {
    /// The file cannot be streamed: unreadable, not MCAP, corrupt.
    #[error("{}: {source}", file.display())]
    Stream {
        /// The file.
        file: PathBuf,
        /// Why.
        #[source]
        source: stream::StreamError,
    },
    /// A folder without MCAP files.
    #[error("{}: no .mcap files in this folder{hint}", folder.display())]
    EmptyFolder {
        /// The folder.
        folder: PathBuf,
        /// What is there instead.
        hint: String,
    },
    /// A signal's topic has no messages.
    #[error("{}: no messages on topic {topic} ({signal}); the log's topics: {available}; \
             name the right one with --topic {signal}=TOPIC", file.display())]
    MissingTopic {
        /// The file.
        file: PathBuf,
        /// `pose`, `imu`, ...
        signal: &'static str,
        /// The topic looked for.
        topic: String,
        /// The topics the log holds, with their types.
        available: String,
    },
    /// A topic whose type is not the signal's.
    #[error("{}: topic {topic} ({signal}) is {found}, expected {expected} in cdr; name the right \
             topic with --topic {signal}=TOPIC", file.display())]
    WrongType {
        /// The file.
        file: PathBuf,
        /// The signal.
        signal: &'static str,
        /// The topic.
        topic: String,
        /// The schema name and message encoding found.
        found: String,
        /// The types accepted.
        expected: &'static str,
    },
    /// A schema whose embedded definition differs from the one the reader decodes.
    #[error("{}: topic {topic} is {type_name}, but {detail}: the log was recorded with another \
             definition of the type; convert it, or report the definition", file.display())]
    Definition {
        /// The file.
        file: PathBuf,
        /// The topic.
        topic: String,
        /// The schema name.
        type_name: String,
        /// What differs.
        detail: String,
    },
    /// A message that does not decode as its type.
    #[error("{}: topic {topic} ({type_name}), message {index} at log time {t} ns: {source}",
            file.display())]
    Decode {
        /// The file.
        file: PathBuf,
        /// The topic.
        topic: String,
        /// The schema name.
        type_name: String,
        /// Index of the message on its topic (0-based).
        index: u64,
        /// Log time, ns.
        t: u64,
        /// What is wrong.
        #[source]
        source: cdr::CdrError,
    },
    /// The log's clock jumps back: two time bases in one log.
    #[error("{}: topic {topic}: the log time jumps back by {back_s:.3} s at message {index} \
             (log time {t} ns): the log mixes two clocks (a clock reset?); split it at that time \
             (e.g. `mcap filter --end`) and score the parts", file.display())]
    ClockBack {
        /// The file.
        file: PathBuf,
        /// The topic.
        topic: String,
        /// Index of the message on its topic.
        index: u64,
        /// Its log time, ns.
        t: u64,
        /// How far back, s.
        back_s: f64,
    },
    /// No IMU and a pose type without twist.
    #[error("{}: no messages on topic {imu} (imu) and the pose topic {pose} is \
             geometry_msgs/msg/PoseStamped, which has no twist to take the acceleration from; \
             the log's topics: {available}; name the IMU with --topic imu=TOPIC", file.display())]
    NoMotion {
        /// The file.
        file: PathBuf,
        /// The IMU topic looked for.
        imu: String,
        /// The pose topic.
        pose: String,
        /// The topics the log holds.
        available: String,
    },
    /// The file changed between the check of the log and the making of its frames.
    #[error(
        "{}: the file changed while it was read (its size or its pose and IMU messages differ \
         from the first pass's): score it again once it is written",
        file.display()
    )]
    Changed {
        /// The file (the log's first).
        file: PathBuf,
    },
    /// The frames are invalid (a value that is not finite).
    #[error("{}: {source}", file.display())]
    Frames {
        /// The file.
        file: PathBuf,
        /// Which tick and field.
        #[source]
        source: TelemetryError,
    },
    /// A frame period outside the monitor's range.
    #[error("frame period {dt} s is outside 0.001..1 s (--set dt=...)")]
    Period {
        /// The period asked.
        dt: f64,
    },
    /// `--topic` options that cannot be (a signal named twice, one topic for two signals,
    /// topics without a log, a log where none is read).
    #[error("{0}")]
    Options(String),
    /// `mcap.max_hold` outside its range.
    #[error("mcap.max_hold {max_hold} s is outside 0.001..60 s (--set mcap.max_hold=SECONDS)")]
    MaxHold {
        /// The hold asked.
        max_hold: f64,
    },
    /// A log that does not exist or cannot be opened: nothing is scored (as a results file that
    /// cannot be read).
    #[error("{}: cannot read: {source}", file.display())]
    Unreadable {
        /// The file (or folder) given.
        file: PathBuf,
        /// Why.
        #[source]
        source: std::io::Error,
    },
    /// Two logs with one route name (the file stem): their routes would share an id.
    #[error("logs {} and {} are both route {name}: a route id is scored once (the same log given \
             twice, or two logs with one file name); give each log once, renamed apart if they \
             are different drives", first.display(), second.display())]
    Duplicate {
        /// The route name.
        name: String,
        /// The first log.
        first: PathBuf,
        /// The second.
        second: PathBuf,
    },
    /// Every pose at one log time: no drive.
    #[error("{}: its {poses} pose message(s) on {topic} all have log time {t} ns: a drive needs \
             poses at two times at least; check the recorder's clock or the pose topic \
             (--topic pose=TOPIC)", file.display())]
    NoDrive {
        /// The file.
        file: PathBuf,
        /// The pose topic.
        topic: String,
        /// Pose messages.
        poses: usize,
        /// Their one time, ns.
        t: u64,
    },
}

/// Whether a log time goes back by more than this (in one topic, in file order) is a clock
/// jump rather than recording jitter (chunks written out of order) **\[decision\]**.
pub const CLOCK_BACK_NS: u64 = 1_000_000_000;

/// The MCAP files of `path`: the file itself, or a rosbag2 folder's `*.mcap` files in name
/// order. Only regular files inside the folder are read: a link (to a file outside it, say) is
/// left out with a note, and its target is never opened.
fn files_of(path: &Path, notes: &mut Vec<String>) -> Result<Vec<PathBuf>, McapError> {
    let meta = std::fs::metadata(path).map_err(|source| McapError::Unreadable {
        file: path.to_path_buf(),
        source,
    })?;
    if !meta.is_dir() {
        return Ok(vec![path.to_path_buf()]);
    }
    let io = |e: std::io::Error| McapError::Stream {
        file: path.to_path_buf(),
        source: e.into(),
    };
    let mut all: Vec<(PathBuf, std::fs::FileType)> = std::fs::read_dir(path)
        .map_err(io)?
        .filter_map(|e| e.ok().and_then(|e| Some((e.path(), e.file_type().ok()?))))
        .collect();
    all.sort_by(|a, b| a.0.cmp(&b.0));
    let is_mcap = |p: &Path| p.extension().is_some_and(|e| e == "mcap");
    let mut mcaps = Vec::new();
    for (p, kind) in &all {
        if !is_mcap(p) {
            continue;
        }
        if kind.is_file() {
            mcaps.push(p.clone());
        } else {
            let what = if kind.is_symlink() {
                "a symbolic link"
            } else {
                "not a regular file"
            };
            notes.push(format!(
                "{} is {what}: left out (sds reads only the regular files inside a rosbag2 \
                 folder)",
                p.file_name().unwrap_or_default().to_string_lossy()
            ));
        }
    }
    if mcaps.is_empty() {
        let hint = if all
            .iter()
            .any(|(p, _)| p.extension().is_some_and(|e| e == "db3"))
        {
            ": it holds sqlite3 (.db3) storage; convert it with `ros2 bag convert` to MCAP"
        } else if !notes.is_empty() {
            ": its .mcap entries are links or not regular files, which sds does not follow"
        } else {
            ""
        };
        return Err(McapError::EmptyFolder {
            folder: path.to_path_buf(),
            hint: hint.into(),
        });
    }
    Ok(mcaps)
}

/// The route name of a log: the file stem, or the folder's name.
pub fn log_name(path: &Path) -> String {
    let name = if path.is_dir() {
        path.file_name()
    } else {
        path.file_stem()
    };
    name.map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| path.display().to_string())
}

/// The clock of one topic in file order: how many messages came out of time order, and the
/// first jump back by more than [`CLOCK_BACK_NS`].
#[derive(Debug, Default)]
struct Order {
    max: u64,
    n: u64,
    late: u64,
    /// (index on the topic, log time, how far back in ns) of the first jump back.
    back: Option<(u64, u64, u64)>,
}

impl Order {
    fn see(&mut self, t: u64) {
        if t < self.max {
            if self.max - t > CLOCK_BACK_NS && self.back.is_none() {
                self.back = Some((self.n, t, self.max - t));
            }
            self.late += 1;
        }
        self.max = self.max.max(t);
        self.n += 1;
    }

    fn check(&self, file: &Path, topic: &str) -> Result<u64, McapError> {
        match self.back {
            Some((index, t, back)) => Err(McapError::ClockBack {
                file: file.to_path_buf(),
                topic: topic.to_string(),
                index,
                t,
                back_s: back as f64 * 1e-9,
            }),
            None => Ok(self.late),
        }
    }
}

pub use self::frames::FAR_NS;

/// A message of one of the signals, decoded.
enum Decoded {
    Pose(PoseSample),
    Imu(MotionSample),
    Event(u64, String),
    Path(Vec<[f64; 3]>),
}

/// Streams one file, decoding the messages of the topics `wanted` reads (a subset of `topics`'
/// signals) to `on`: each channel's type and definition checked once, each message decoded.
fn decode_file(
    file: &Path,
    topics: &Topics,
    wanted: &dyn Fn(&str) -> bool,
    on: &mut dyn FnMut(Decoded),
) -> Result<stream::Streamed, McapError> {
    // Checked once per channel (ids are per file).
    let mut checked: BTreeMap<u16, RosType> = BTreeMap::new();
    let mut index: BTreeMap<u16, u64> = BTreeMap::new();
    let mut failure: Option<McapError> = None;
    let streamed = stream::stream(file, wanted, |m| {
        let ch = m.channel;
        let (type_name, schema_enc, schema_data) = match &ch.schema {
            Some(s) => (s.name.as_str(), s.encoding.as_str(), &s.data[..]),
            None => ("", "", &[][..]),
        };
        let encoding = ch.message_encoding.as_str();
        let i = index.entry(ch.id).or_default();
        let at = *i;
        *i += 1;
        if Some(&ch.topic) == topics.event.as_ref() {
            on(Decoded::Event(m.log_time, type_name.to_string()));
            return Ok(());
        }
        type Signal = (&'static str, &'static [RosType], &'static str);
        let signal: Signal = if ch.topic == topics.pose {
            (
                "pose",
                &[RosType::Odometry, RosType::PoseStamped],
                "nav_msgs/msg/Odometry or geometry_msgs/msg/PoseStamped",
            )
        } else if ch.topic == topics.imu {
            ("imu", &[RosType::Imu], "sensor_msgs/msg/Imu")
        } else {
            ("path", &[RosType::Path], "nav_msgs/msg/Path")
        };
        let (signal, accepted, expected) = signal;
        let t = match checked.get(&ch.id) {
            Some(t) => *t,
            None => {
                let found = RosType::of(type_name).filter(|t| accepted.contains(t));
                let Some(t) = found.filter(|_| encoding == "cdr") else {
                    failure = Some(McapError::WrongType {
                        file: file.to_path_buf(),
                        signal,
                        topic: ch.topic.clone(),
                        found: if type_name.is_empty() {
                            format!("without a schema, in {encoding:?}")
                        } else {
                            format!("{type_name} in {encoding:?}")
                        },
                        expected,
                    });
                    return Err(String::new());
                };
                let text = String::from_utf8_lossy(schema_data);
                if let Err(detail) = messages::check_definition(t, schema_enc, &text) {
                    failure = Some(McapError::Definition {
                        file: file.to_path_buf(),
                        topic: ch.topic.clone(),
                        type_name: type_name.into(),
                        detail,
                    });
                    return Err(String::new());
                }
                checked.insert(ch.id, t);
                t
            }
        };
        let decoded = match t {
            RosType::Odometry | RosType::PoseStamped => messages::decode_pose(t, m.data).map(|p| {
                Decoded::Pose(PoseSample {
                    t: m.log_time,
                    position: p.position,
                    yaw: messages::yaw(p.orientation),
                    twist: p.twist,
                })
            }),
            RosType::Imu => messages::decode_imu(m.data).map(|i| {
                Decoded::Imu(MotionSample {
                    t: m.log_time,
                    acc: i.acc,
                    world: false,
                    yaw_rate: i.yaw_rate,
                })
            }),
            RosType::Path => messages::decode_path(m.data).map(Decoded::Path),
        };
        match decoded {
            Ok(d) => {
                on(d);
                Ok(())
            }
            Err(source) => {
                failure = Some(McapError::Decode {
                    file: file.to_path_buf(),
                    topic: ch.topic.clone(),
                    type_name: type_name.into(),
                    index: at,
                    t: m.log_time,
                    source,
                });
                Err(String::new())
            }
        }
    });
    match (streamed, failure) {
        (_, Some(f)) => Err(f),
        (Err(e), None) => Err(McapError::Stream {
            file: file.to_path_buf(),
            source: e,
        }),
        (Ok(s), None) => Ok(s),
    }
}

/// A log read once through (docs/SCORE.md §2.4), everything checked, nothing of its poses and IMU
/// samples kept: what [`LogScan::frames`] needs to frame it on a second pass, in bounded memory.
#[derive(Debug)]
pub struct LogScan {
    /// The route's name: the file stem, or the rosbag2 folder's name.
    pub name: String,
    /// The file (or folder) given.
    pub path: PathBuf,
    /// The MCAP files read, in order.
    pub files: Vec<PathBuf>,
    /// The period, s.
    pub dt: f64,
    /// The events of the event topic, (log time ns, schema name), in time order.
    pub events: Vec<(u64, String)>,
    /// The reference path (x, y, z), from the last message of the path topic.
    pub path_points: Option<Vec<[f64; 3]>>,
    /// Messages read (all topics).
    pub messages: u64,
    /// Bytes of the files.
    pub bytes: u64,
    topics: Topics,
    max_hold: f64,
    dt_ns: u64,
    hold_ns: u64,
    /// What the first pass saw of the poses and IMU: the second must see the same.
    seen: Seen,
    /// Notes of the first pass (cuts, corrupt chunks, order, the IMU fallback).
    notes: Vec<String>,
    /// Path messages.
    path_messages: u64,
    /// The path topic named but without messages: said after the frames (whose errors come
    /// first).
    path_missing: Option<McapError>,
}

/// What a pass over a log saw of the signals the frames are made of: each file's size, and per
/// signal the messages and the latest log time. The two passes must agree (the file did not
/// change between them).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
struct Seen {
    bytes: u64,
    poses: (u64, u64),
    imu: (u64, u64),
}

/// One frame of a log as [`LogScan::frames`] makes it.
#[derive(Debug, Clone, Copy)]
pub struct LogTick<'a> {
    /// The frame (step = tick index).
    pub frame: &'a crate::input::telemetry::TelemetryFrame,
    /// Tick time, ns.
    pub t: u64,
    /// Index of the frame in the log.
    pub index: usize,
    /// The frame starts a segment (the first frame included).
    pub new_segment: bool,
    /// The events that fall on it (indices into [`LogScan::events`]).
    pub events: &'a [usize],
}

/// What framing a log gave besides its frames.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct LogFramed {
    /// Frames made.
    pub frames: u64,
    /// Ticks missing between the first frame and the last (inside gaps).
    pub gaps: u64,
    /// Segments (at least 1).
    pub segments: u64,
    /// The frame each event falls on ([`LogEvent::frame`]), in [`LogScan::events`] order.
    pub event_frames: Vec<Option<usize>>,
    /// Everything the reader noted, in order (the log's path not repeated).
    pub notes: Vec<String>,
}

/// A sample waiting for the samples of other times that may still come before it (messages out
/// of order within [`CLOCK_BACK_NS`]): ordered by time, then file order.
struct Waiting {
    t: u64,
    seq: u64,
    sample: Sample,
}

impl PartialEq for Waiting {
    fn eq(&self, other: &Self) -> bool {
        (self.t, self.seq) == (other.t, other.seq)
    }
}
impl Eq for Waiting {}
impl PartialOrd for Waiting {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Waiting {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        (self.t, self.seq).cmp(&(other.t, other.seq))
    }
}

/// Reads the log at `path` once through (every check of [`read_log`] but the frames') without
/// keeping its poses and IMU samples; [`LogScan::frames`] then makes its frames.
///
/// ```no_run
/// use monitor_host::input::mcap::{scan_log, Topics};
/// let mut scan = scan_log("drive.mcap".as_ref(), &Topics::default(), 0.05, 0.25)?;
/// let mut distance = 0.0;
/// let mut last: Option<[f64; 2]> = None;
/// let framed = scan.frames(|tick| {
///     let [x, y] = tick.frame.location;
///     if let (false, Some([a, b])) = (tick.new_segment, last) {
///         distance += (x - a).hypot(y - b);
///     }
///     last = Some([x, y]);
/// })?;
/// println!("{} frames, {} segments, {distance:.0} m", framed.frames, framed.segments);
/// # Ok::<(), monitor_host::input::mcap::McapError>(())
/// ```
///
/// # Errors
/// [`McapError`] naming the file, the topic and the fix.
pub fn scan_log(
    path: &Path,
    topics: &Topics,
    dt: f64,
    max_hold: f64,
) -> Result<LogScan, McapError> {
    if !(1e-3..=1.0).contains(&dt) {
        return Err(McapError::Period { dt });
    }
    if !(1e-3..=60.0).contains(&max_hold) {
        return Err(McapError::MaxHold { max_hold });
    }
    let dt_ns = (dt * 1e9).round() as u64;
    let hold_ns = (max_hold * 1e9).round() as u64;
    let mut notes = Vec::new();
    let files = files_of(path, &mut notes)?;
    // A note names a file inside a rosbag2 folder; a single file is the log the warning names.
    let folder = files.len() > 1 || files.first().is_some_and(|f| f != path);
    let label = |f: &Path| {
        if folder {
            format!("{}: ", f.file_name().unwrap_or_default().to_string_lossy())
        } else {
            String::new()
        }
    };
    let mut seen: BTreeMap<String, stream::TopicCount> = BTreeMap::new();
    let (mut pose_order, mut imu_order) = (Order::default(), Order::default());
    let mut pose_min = u64::MAX;
    let mut any_twist = false;
    let mut events: Vec<(u64, String)> = Vec::new();
    let mut path_msgs: (u64, Option<Vec<[f64; 3]>>) = (0, None);
    let (mut messages, mut bytes) = (0u64, 0u64);
    for file in &files {
        let streamed = decode_file(file, topics, &|t| topics.reads(t), &mut |d| match d {
            Decoded::Pose(p) => {
                pose_order.see(p.t);
                pose_min = pose_min.min(p.t);
                any_twist |= p.twist.is_some();
            }
            Decoded::Imu(m) => imu_order.see(m.t),
            Decoded::Event(t, kind) => events.push((t, kind)),
            Decoded::Path(p) => path_msgs = (path_msgs.0 + 1, Some(p)),
        })?;
        messages += streamed.messages;
        bytes += streamed.bytes;
        for (topic, c) in streamed.topics {
            let entry = seen.entry(topic).or_default();
            if entry.type_name.is_empty() {
                entry.type_name = c.type_name;
                entry.encoding = c.encoding;
            }
            entry.messages += c.messages;
        }
        for c in &streamed.corrupt_chunks {
            let lost = c
                .messages
                .map_or_else(String::new, |n| format!(" ({n} messages)"));
            notes.push(format!(
                "{}chunk {} (byte {}, log time {}..{} ns) is corrupt: {}; its messages{lost} are \
                 left out, the chunks after it are read",
                label(file),
                c.index,
                c.offset,
                c.times.0,
                c.times.1,
                c.reason
            ));
        }
        if let Some(cut) = streamed.truncated {
            notes.push(format!(
                "{}{}: {} messages recovered; the last {} bytes are lost (about {} messages, \
                 estimated from the mean message size: the index that would count them was in \
                 the lost end of the file)",
                label(file),
                cut.reason,
                streamed.messages,
                cut.lost_bytes,
                cut.lost_messages_estimate
            ));
        }
    }
    let first = files.first().cloned().unwrap_or_default();
    let available = || {
        if seen.is_empty() {
            return "none (no messages)".to_string();
        }
        seen.iter()
            .map(|(t, s)| format!("{t} ({}, {} messages)", s.type_name, s.messages))
            .collect::<Vec<_>>()
            .join(", ")
    };
    if pose_order.n == 0 {
        return Err(McapError::MissingTopic {
            file: first,
            signal: "pose",
            topic: topics.pose.clone(),
            available: available(),
        });
    }
    for (what, late) in [
        ("pose", pose_order.check(&first, &topics.pose)?),
        ("imu", imu_order.check(&first, &topics.imu)?),
    ] {
        if late > 0 {
            let topic = if what == "pose" {
                &topics.pose
            } else {
                &topics.imu
            };
            notes.push(format!(
                "topic {topic} ({what}): {late} messages came out of log-time order (chunks \
                 written out of order); they were put in time order"
            ));
        }
    }
    if pose_min == pose_order.max {
        return Err(McapError::NoDrive {
            file: first,
            topic: topics.pose.clone(),
            poses: pose_order.n as usize,
            t: pose_min,
        });
    }
    events.sort_by_key(|e| e.0);
    let twist = imu_order.n == 0;
    if twist {
        if !any_twist {
            return Err(McapError::NoMotion {
                file: first,
                imu: topics.imu.clone(),
                pose: topics.pose.clone(),
                available: available(),
            });
        }
        notes.push(format!(
            "no messages on topic {} (imu): acceleration and yaw rate come from differences of \
             the odometry twist on {} (name an IMU with --topic imu=TOPIC)",
            topics.imu, topics.pose
        ));
    }
    let path_missing = match (&topics.path, &path_msgs.1) {
        (Some(p), None) => Some(McapError::MissingTopic {
            file: first,
            signal: "path",
            topic: p.clone(),
            available: available(),
        }),
        _ => None,
    };
    Ok(LogScan {
        name: log_name(path),
        path: path.to_path_buf(),
        files,
        dt,
        events,
        path_points: path_msgs.1,
        messages,
        bytes,
        topics: topics.clone(),
        max_hold,
        dt_ns,
        hold_ns,
        seen: Seen {
            bytes,
            poses: (pose_order.n, pose_order.max),
            imu: (imu_order.n, imu_order.max),
        },
        notes,
        path_messages: path_msgs.0,
        path_missing,
    })
}

impl LogScan {
    /// Reads the log's poses and IMU a second time and makes its frames as they stream
    /// (docs/SCORE.md §2.4, [`frames::Framer`]), each given to `each` with the events that fall on
    /// it: in bounded memory, whatever the log's length (messages out of order wait at most
    /// [`CLOCK_BACK_NS`], a frame one tick for the events after it).
    ///
    /// # Errors
    /// [`McapError::Frames`] naming the tick of a value that is not finite, or when no tick has
    /// every signal; the path topic without messages; the file changed since the first pass.
    pub fn frames(&mut self, mut each: impl FnMut(&LogTick<'_>)) -> Result<LogFramed, McapError> {
        let first = self.files.first().cloned().unwrap_or_default();
        let frames_err = |source| McapError::Frames {
            file: first.clone(),
            source,
        };
        let (dt_ns, hold_ns) = (self.dt_ns, self.hold_ns);
        let events = &self.events;
        let mut framer = frames::Framer::new(dt_ns, hold_ns);
        // No IMU messages: the motion comes from the odometry twist.
        let mut twist = (self.seen.imu.0 == 0).then(|| frames::TwistMotion::new(hold_ns));
        let mut event_frames: Vec<Option<usize>> = vec![None; events.len()];
        // The latest frame, held until the next one says which events fall on it.
        let mut held: Option<(frames::Tick, usize)> = None;
        let mut on_held: Vec<usize> = Vec::new();
        let mut next_event = 0usize;
        let mut index = 0usize;
        let mut emit = |held: &(frames::Tick, usize), on: &[usize]| {
            each(&LogTick {
                frame: &held.0.frame,
                t: held.0.t,
                index: held.1,
                new_segment: held.0.new_segment,
                events: on,
            })
        };
        // Each tick resolves the events up to its time: the first tick at or after an event,
        // within the hold; else the tick just before it, within one period.
        let mut tick = |tick: frames::Tick| {
            let mut on_cur = Vec::new();
            while let Some((t, _)) = events.get(next_event) {
                if *t > tick.t {
                    break;
                }
                if tick.t - t <= hold_ns {
                    on_cur.push(next_event);
                    event_frames[next_event] = Some(index);
                } else if let Some((_, k)) = held.as_ref().filter(|(h, _)| t - h.t < dt_ns) {
                    on_held.push(next_event);
                    event_frames[next_event] = Some(*k);
                }
                next_event += 1;
            }
            if let Some(h) = held.take() {
                emit(&h, &on_held);
            }
            on_held = on_cur;
            held = Some((tick, index));
            index += 1;
        };
        let mut heap: std::collections::BinaryHeap<std::cmp::Reverse<Waiting>> =
            std::collections::BinaryHeap::new();
        let (mut pose_order, mut imu_order) = (Order::default(), Order::default());
        let mut bytes = 0u64;
        let mut seq = 0u64;
        let mut failed: Option<McapError> = None;
        let mut feed = |s: Sample, framer: &mut frames::Framer| -> Result<(), TelemetryError> {
            if let (Some(tw), Sample::Pose(p)) = (twist.as_mut(), &s) {
                if let Some(m) = tw.push(*p) {
                    framer.push(Sample::Motion(m), &mut tick)?;
                }
            }
            framer.push(s, &mut tick)
        };
        let (poses, imu) = (self.seen.poses.0, self.seen.imu.0);
        let pose_topic = self.topics.pose.clone();
        let imu_topic = self.topics.imu.clone();
        let wanted = |t: &str| t == pose_topic || t == imu_topic;
        for file in &self.files {
            let mut on = |d: Decoded| {
                if failed.is_some() {
                    return;
                }
                let sample = match d {
                    Decoded::Pose(p) => {
                        pose_order.see(p.t);
                        Sample::Pose(p)
                    }
                    Decoded::Imu(m) => {
                        imu_order.see(m.t);
                        Sample::Motion(m)
                    }
                    _ => return,
                };
                heap.push(std::cmp::Reverse(Waiting {
                    t: sample.t(),
                    seq,
                    sample,
                }));
                seq += 1;
                // A sample is in its place once every topic still to come is past it by more
                // than a clock may go back (the first pass checked that none goes further).
                let mark = |seen: u64, all: u64, max: u64| {
                    if seen >= all {
                        u64::MAX
                    } else {
                        max.saturating_sub(CLOCK_BACK_NS)
                    }
                };
                let w = mark(pose_order.n, poses, pose_order.max).min(mark(
                    imu_order.n,
                    imu,
                    imu_order.max,
                ));
                while heap.peek().is_some_and(|top| top.0.t < w) {
                    let Some(std::cmp::Reverse(top)) = heap.pop() else {
                        break;
                    };
                    if let Err(e) = feed(top.sample, &mut framer) {
                        failed = Some(frames_err(e));
                        return;
                    }
                }
            };
            let wanted_here: &dyn Fn(&str) -> bool = &wanted;
            bytes += decode_file(file, &self.topics, wanted_here, &mut on)?.bytes;
        }
        if let Some(e) = failed {
            return Err(e);
        }
        let seen = Seen {
            bytes,
            poses: (pose_order.n, pose_order.max),
            imu: (imu_order.n, imu_order.max),
        };
        if seen != self.seen {
            return Err(McapError::Changed { file: first });
        }
        while let Some(std::cmp::Reverse(top)) = heap.pop() {
            feed(top.sample, &mut framer).map_err(frames_err)?;
        }
        if let Some(m) = twist.as_mut().and_then(|tw| tw.finish()) {
            framer
                .push(Sample::Motion(m), &mut tick)
                .map_err(frames_err)?;
        }
        let done = framer.finish(&mut tick).map_err(frames_err)?;
        // The events after the last frame fall on it within one period.
        if let Some((h, k)) = &held {
            for (i, (t, _)) in events.iter().enumerate().skip(next_event) {
                if t - h.t < dt_ns {
                    on_held.push(i);
                    event_frames[i] = Some(*k);
                }
            }
        }
        if let Some(h) = held.take() {
            emit(&h, &on_held);
        }
        if let Some(e) = self.path_missing.take() {
            return Err(e);
        }
        let (dt, max_hold) = (self.dt, self.max_hold);
        let mut notes = self.notes.clone();
        let segments = done.segments.max(1);
        if done.pose_gap_count > 0 {
            notes.push(format!(
                "{} gap(s) longer than mcap.max_hold = {max_hold} s between pose messages (the \
                 recorder paused, a topic stopped): no tick is made inside a gap and nothing is \
                 held across it; the frames form {segments} segment(s), each scored as a fresh \
                 start; {} of {} ticks at {dt} s fall in gaps",
                done.pose_gap_count,
                done.missing,
                done.missing + done.frames,
            ));
        } else if done.missing > 0 {
            notes.push(format!(
                "{} of {} ticks at {dt} s have no IMU message within mcap.max_hold = {max_hold} \
                 s: they count as gaps, and the log is cut into {segments} segment(s) there",
                done.missing,
                done.missing + done.frames,
            ));
        }
        for &(a, b) in &done.far_gaps {
            notes.push(format!(
                "pose messages at log time {a} ns and {b} ns lie {:.0} s apart: a message far \
                 from the rest (a clock that was not set? a stray time stamp?); the ticks between \
                 count as gaps",
                (b - a) as f64 * 1e-9
            ));
        }
        if self.path_messages > 1 {
            notes.push(format!(
                "{} messages on the path topic: the last one is the lateral reference",
                self.path_messages
            ));
        }
        if let (Some(p), Some(t)) = (&self.topics.path, &self.path_points) {
            if t.len() < 2 {
                notes.push(format!(
                    "the path on {p} has {} poses: no lateral reference",
                    t.len()
                ));
            }
        }
        Ok(LogFramed {
            frames: done.frames,
            gaps: done.missing,
            segments,
            event_frames,
            notes,
        })
    }

    /// The reference path, when it has two poses at least.
    pub fn reference_path(&self) -> Option<&[[f64; 3]]> {
        self.path_points.as_deref().filter(|p| p.len() >= 2)
    }
}

/// Reads the log at `path` (an `.mcap` file or a rosbag2 folder) and makes its frames at the
/// period `dt` (s), cut into segments at gaps longer than `max_hold` (s), as docs/SCORE.md §2.4
/// defines them: [`scan_log`] and [`LogScan::frames`], the frames kept. Scoring does not keep
/// them (`crate::pipeline::drive`).
///
/// # Errors
/// [`McapError`] naming the file, the topic and the fix.
pub fn read_log(
    path: &Path,
    topics: &Topics,
    dt: f64,
    max_hold: f64,
) -> Result<VehicleLog, McapError> {
    let mut scan = scan_log(path, topics, dt, max_hold)?;
    let (mut frames, mut segments, mut times) = (Vec::new(), Vec::new(), Vec::new());
    let framed = scan.frames(|tick| {
        if tick.new_segment {
            segments.push(frames.len());
        }
        frames.push(*tick.frame);
        times.push(tick.t);
    })?;
    let events = std::mem::take(&mut scan.events)
        .into_iter()
        .zip(&framed.event_frames)
        .map(|((t, kind), frame)| LogEvent {
            t,
            frame: *frame,
            kind,
        })
        .collect();
    Ok(VehicleLog {
        name: scan.name,
        path: scan.path,
        files: scan.files,
        telemetry: Telemetry {
            frames,
            gaps: framed.gaps,
            segments,
        },
        times,
        dt,
        events,
        path_points: scan.path_points.filter(|p| p.len() >= 2),
        messages: scan.messages,
        bytes: scan.bytes,
        notes: framed.notes,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::demo::drive::{write_weave, Weave};

    /// Review of issue 48, item 8: a log rewritten between the first pass and the frames is
    /// refused, naming it; the same log again frames.
    #[test]
    fn a_log_changed_between_the_passes_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let log = dir.path().join("drive.mcap");
        let weave = |seconds| Weave {
            seconds,
            ..Weave::default()
        };
        write_weave(&log, &weave(60)).unwrap();
        let topics = Topics::default();
        let mut scan = scan_log(&log, &topics, 0.05, 0.25).unwrap();
        write_weave(&log, &weave(60)).unwrap();
        let framed = scan.frames(|_| {}).unwrap();
        assert_eq!(framed.frames, 1_200);
        let mut scan = scan_log(&log, &topics, 0.05, 0.25).unwrap();
        write_weave(&log, &weave(61)).unwrap();
        let e = scan.frames(|_| {}).unwrap_err();
        assert!(
            matches!(&e, McapError::Changed { file } if *file == log),
            "{e}"
        );
        assert!(
            e.to_string().contains("the file changed while it was read"),
            "{e}"
        );
    }
}
