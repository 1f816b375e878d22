//! Vehicle logs of the project's own making, for the tests and the drive-memory benchmark
//! (docs/SCORE.md §2.4): ROS 2 messages in CDR written here, the `mcap` crate's writer. The one
//! writer the tests of `sds score --mcap`, the streamed drive and `examples/write_drive.rs` use.
//!
//! ```
//! use monitor_host::demo::drive::{write_weave, Weave};
//! let dir = tempfile::tempdir()?;
//! let log = dir.path().join("drive.mcap");
//! write_weave(&log, &Weave { seconds: 60, ..Weave::default() })?;
//! assert!(std::fs::metadata(&log)?.len() > 60 * 20 * 2 * 300);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::collections::BTreeMap;
use std::path::Path;

/// `nav_msgs/msg/Odometry`'s definition.
pub const ODOMETRY: &str = "std_msgs/Header header\nstring child_frame_id\n\
    geometry_msgs/PoseWithCovariance pose\ngeometry_msgs/TwistWithCovariance twist\n";
/// `sensor_msgs/msg/Imu`'s definition.
pub const IMU: &str = "std_msgs/Header header\ngeometry_msgs/Quaternion orientation\n\
    float64[9] orientation_covariance\ngeometry_msgs/Vector3 angular_velocity\n\
    float64[9] angular_velocity_covariance\ngeometry_msgs/Vector3 linear_acceleration\n\
    float64[9] linear_acceleration_covariance\n";
/// `nav_msgs/msg/Path`'s definition.
pub const PATH: &str = "std_msgs/Header header\ngeometry_msgs/PoseStamped[] poses\n";
/// `geometry_msgs/msg/PoseStamped`'s definition.
pub const POSE_STAMPED: &str = "std_msgs/Header header\ngeometry_msgs/Pose pose\n";

/// A ROS 2 message in CDR (little-endian), aligned from the end of its 4-byte header.
#[derive(Clone, Debug)]
pub struct Cdr(pub Vec<u8>);

impl Default for Cdr {
    fn default() -> Self {
        Cdr::new()
    }
}

impl Cdr {
    /// The encapsulation header alone.
    pub fn new() -> Cdr {
        Cdr(vec![0, 1, 0, 0])
    }
    fn align(&mut self, n: usize) {
        while !(self.0.len() - 4).is_multiple_of(n) {
            self.0.push(0);
        }
    }
    /// A `uint32` (a sequence's length too).
    pub fn u32(&mut self, v: u32) -> &mut Self {
        self.align(4);
        self.0.extend_from_slice(&v.to_le_bytes());
        self
    }
    /// A `float64`.
    pub fn f64(&mut self, v: f64) -> &mut Self {
        self.align(8);
        self.0.extend_from_slice(&v.to_le_bytes());
        self
    }
    /// `float64`s, one after the other.
    pub fn f64s(&mut self, v: &[f64]) -> &mut Self {
        for x in v {
            self.f64(*x);
        }
        self
    }
    /// A `string`.
    pub fn string(&mut self, s: &str) -> &mut Self {
        self.u32(s.len() as u32 + 1);
        self.0.extend_from_slice(s.as_bytes());
        self.0.push(0);
        self
    }
    /// A `std_msgs/Header` stamped `t` (ns) in frame `map`.
    pub fn header(&mut self, t: u64) -> &mut Self {
        self.u32((t / 1_000_000_000) as u32)
            .u32((t % 1_000_000_000) as u32)
            .string("map")
    }
}

/// An odometry message at `t`: position `(x, y)`, heading `yaw`, forward speed `vx` and yaw
/// rate `wz` in its twist.
pub fn odometry(t: u64, [x, y, yaw]: [f64; 3], vx: f64, wz: f64) -> Vec<u8> {
    let mut c = Cdr::new();
    c.header(t).string("base_link");
    c.f64s(&[x, y, 0.0, 0.0, 0.0, (yaw / 2.0).sin(), (yaw / 2.0).cos()]);
    c.f64s(&[0.0; 36])
        .f64s(&[vx, 0.0, 0.0, 0.0, 0.0, wz])
        .f64s(&[0.0; 36]);
    c.0
}

/// An IMU message at `t`: yaw rate `wz`, acceleration `a` (m/s², gravity included or not).
pub fn imu(t: u64, a: [f64; 3], wz: f64) -> Vec<u8> {
    let mut c = Cdr::new();
    c.header(t).f64s(&[0.0, 0.0, 0.0, 1.0]).f64s(&[0.0; 9]);
    c.f64s(&[0.0, 0.0, wz])
        .f64s(&[0.0; 9])
        .f64s(&a)
        .f64s(&[0.0; 9]);
    c.0
}

/// How a log is written.
#[derive(Clone, Copy, Debug)]
pub struct LogOptions {
    /// Messages in chunks (else loose records).
    pub chunked: bool,
    /// A chunk's size, bytes.
    pub chunk_size: u64,
    /// Chunks compressed with zstd.
    pub zstd: bool,
    /// A message index after each chunk.
    pub indexed: bool,
}

impl Default for LogOptions {
    /// Chunks of 256 KiB, uncompressed, indexed.
    fn default() -> Self {
        LogOptions {
            chunked: true,
            chunk_size: 1 << 18,
            zstd: false,
            indexed: true,
        }
    }
}

/// An MCAP log being written, one channel (and schema) per topic as first met; holds one
/// chunk at a time.
pub struct LogWriter {
    w: mcap::Writer<std::io::BufWriter<std::fs::File>>,
    channels: BTreeMap<String, u16>,
    sequence: u32,
}

impl LogWriter {
    /// Creates the log.
    ///
    /// # Errors
    /// The file cannot be created.
    pub fn create(path: &Path, options: LogOptions) -> Result<LogWriter, mcap::McapError> {
        let file = std::io::BufWriter::new(std::fs::File::create(path)?);
        let w = mcap::WriteOptions::new()
            .use_chunks(options.chunked)
            .chunk_size(Some(options.chunk_size))
            .compression(options.zstd.then_some(mcap::Compression::Zstd))
            .emit_message_indexes(options.indexed)
            .create(file)?;
        Ok(LogWriter {
            w,
            channels: BTreeMap::new(),
            sequence: 0,
        })
    }

    /// A message on `topic` (of `schema`, its ROS 2 `definition`) logged at `t` ns.
    ///
    /// # Errors
    /// From the writer.
    pub fn write(
        &mut self,
        topic: &str,
        schema: &str,
        definition: &str,
        t: u64,
        data: &[u8],
    ) -> Result<(), mcap::McapError> {
        let id = match self.channels.get(topic) {
            Some(id) => *id,
            None => {
                let s = self
                    .w
                    .add_schema(schema, "ros2msg", definition.as_bytes())?;
                let id = self.w.add_channel(s, topic, "cdr", &BTreeMap::new())?;
                self.channels.insert(topic.to_string(), id);
                id
            }
        };
        let header = mcap::records::MessageHeader {
            channel_id: id,
            sequence: self.sequence,
            log_time: t,
            publish_time: t,
        };
        self.sequence += 1;
        self.w.write_to_known_channel(&header, data)
    }

    /// Ends the chunk being written.
    ///
    /// # Errors
    /// From the writer.
    pub fn flush(&mut self) -> Result<(), mcap::McapError> {
        self.w.flush()
    }

    /// Ends the log (summary and footer).
    ///
    /// # Errors
    /// From the writer.
    pub fn finish(mut self) -> Result<(), mcap::McapError> {
        self.w.finish().map(drop)
    }
}

/// A message of [`write_messages`]: `(topic, schema, definition, log time, data)`.
pub type Message<'a> = (&'a str, &'a str, &'a str, u64, Vec<u8>);

/// Writes `messages` in the order given.
///
/// # Errors
/// From the writer.
pub fn write_messages(
    path: &Path,
    options: LogOptions,
    messages: &[Message<'_>],
) -> Result<(), mcap::McapError> {
    let mut w = LogWriter::create(path, options)?;
    for (topic, schema, definition, t, data) in messages {
        w.write(topic, schema, definition, *t, data)?;
    }
    w.finish()
}

/// A drive at 20 Hz along a gentle weave (odometry and IMU), an event on `/events` now and then
/// and a 2 s recorder pause (a gap: a new segment) now and then: [`write_weave`].
#[derive(Clone, Copy, Debug)]
pub struct Weave {
    /// Its length, s.
    pub seconds: u64,
    /// A pause every so many seconds.
    pub pause_every: u64,
    /// An event every so many seconds (half-way through each period).
    pub event_every: u64,
    /// How it is written.
    pub log: LogOptions,
}

impl Default for Weave {
    /// A pause every 10 minutes, an event every 5, chunks of 256 KiB uncompressed.
    fn default() -> Self {
        Weave {
            seconds: 600,
            pause_every: 600,
            event_every: 300,
            log: LogOptions::default(),
        }
    }
}

/// The log's first time stamp, ns.
pub const T0: u64 = 1_700_000_000_000_000_000;

/// Writes the drive `weave` to `path`, a message at a time (an 8-hour log in bounded memory).
///
/// # Errors
/// From the writer.
pub fn write_weave(path: &Path, weave: &Weave) -> Result<(), mcap::McapError> {
    let mut w = LogWriter::create(path, weave.log)?;
    let (pause, event) = (weave.pause_every * 20, weave.event_every * 20);
    let (mut x, mut y, mut yaw) = (0.0f64, 0.0f64, 0.0f64);
    for i in 0..weave.seconds * 20 {
        // The last 2 s of each period: the recorder stopped, a gap.
        if i % pause >= pause - 40 {
            continue;
        }
        let t = T0 + i * 50_000_000;
        let s = i as f64 * 0.05;
        let v = 8.0 + 2.0 * (s / 40.0).sin();
        let wz = 0.15 * (s / 7.0).sin();
        let ax = 0.05 * (s / 40.0).cos() + 0.3 * (s / 3.1).sin();
        yaw += wz * 0.05;
        x += v * yaw.cos() * 0.05;
        y += v * yaw.sin() * 0.05;
        w.write(
            "/odom",
            "nav_msgs/msg/Odometry",
            ODOMETRY,
            t,
            &odometry(t, [x, y, yaw], v, wz),
        )?;
        w.write(
            "/imu",
            "sensor_msgs/msg/Imu",
            IMU,
            t,
            &imu(t, [ax, v * wz, 9.8], wz),
        )?;
        if i % event == event / 2 {
            w.write("/events", "std_msgs/msg/Empty", "", t, &[0, 1, 0, 0])?;
        }
    }
    w.finish()
}
