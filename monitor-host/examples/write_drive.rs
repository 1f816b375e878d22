//! Writes a long vehicle log for the memory benchmark (`bench/drive-memory.sh`, issue 51 goal 2):
//! `cargo run --release -p monitor-host --example write_drive -- OUT.mcap SECONDS`.
//!
//! A drive at 20 Hz along a gentle weave (odometry and IMU, ROS 2 CDR written here, the `mcap`
//! crate's writer, zstd chunks), an event on `/events` every ten minutes and a short recorder
//! pause every half hour (a gap: a new segment). The writer holds one chunk at a time, so an
//! 8-hour log is written in bounded memory.

use std::collections::BTreeMap;
use std::fs;

const ODOMETRY: &str = "std_msgs/Header header\nstring child_frame_id\n\
    geometry_msgs/PoseWithCovariance pose\ngeometry_msgs/TwistWithCovariance twist\n";
const IMU: &str = "std_msgs/Header header\ngeometry_msgs/Quaternion orientation\n\
    float64[9] orientation_covariance\ngeometry_msgs/Vector3 angular_velocity\n\
    float64[9] angular_velocity_covariance\ngeometry_msgs/Vector3 linear_acceleration\n\
    float64[9] linear_acceleration_covariance\n";

/// CDR (little-endian), aligned from the end of the 4-byte header.
struct Cdr(Vec<u8>);

impl Cdr {
    fn new() -> Cdr {
        Cdr(vec![0, 1, 0, 0])
    }
    fn align(&mut self, n: usize) {
        while !(self.0.len() - 4).is_multiple_of(n) {
            self.0.push(0);
        }
    }
    fn u32(&mut self, v: u32) -> &mut Self {
        self.align(4);
        self.0.extend_from_slice(&v.to_le_bytes());
        self
    }
    fn f64s(&mut self, v: &[f64]) -> &mut Self {
        for x in v {
            self.align(8);
            self.0.extend_from_slice(&x.to_le_bytes());
        }
        self
    }
    fn string(&mut self, s: &str) -> &mut Self {
        self.u32(s.len() as u32 + 1);
        self.0.extend_from_slice(s.as_bytes());
        self.0.push(0);
        self
    }
    fn header(&mut self, t: u64) -> &mut Self {
        self.u32((t / 1_000_000_000) as u32)
            .u32((t % 1_000_000_000) as u32)
            .string("map")
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let [_, out, seconds] = &args[..] else {
        return Err("usage: write_drive OUT.mcap SECONDS".into());
    };
    let seconds: u64 = seconds.parse()?;
    let file = std::io::BufWriter::new(fs::File::create(out)?);
    let mut w = mcap::WriteOptions::new()
        .chunk_size(Some(1 << 20))
        .compression(Some(mcap::Compression::Zstd))
        .create(file)?;
    let none = BTreeMap::new();
    let odom_s = w.add_schema("nav_msgs/msg/Odometry", "ros2msg", ODOMETRY.as_bytes())?;
    let imu_s = w.add_schema("sensor_msgs/msg/Imu", "ros2msg", IMU.as_bytes())?;
    let ev_s = w.add_schema("std_msgs/msg/Empty", "ros2msg", b"")?;
    let odom = w.add_channel(odom_s, "/odom", "cdr", &none)?;
    let imu = w.add_channel(imu_s, "/imu", "cdr", &none)?;
    let events = w.add_channel(ev_s, "/events", "cdr", &none)?;
    const T0: u64 = 1_700_000_000_000_000_000;
    const DT: u64 = 50_000_000;
    let (mut x, mut y, mut yaw) = (0.0f64, 0.0f64, 0.0f64);
    for i in 0..seconds * 20 {
        // A 2 s pause every 30 minutes: the recorder stopped, a gap.
        if i % 36_000 >= 35_960 {
            continue;
        }
        let t = T0 + i * DT;
        let s = i as f64 * 0.05;
        let v = 8.0 + 2.0 * (s / 40.0).sin();
        let wz = 0.15 * (s / 7.0).sin();
        let ax = 0.05 * (s / 40.0).cos() + 0.3 * (s / 3.1).sin();
        let ay = v * wz;
        yaw += wz * 0.05;
        x += v * yaw.cos() * 0.05;
        y += v * yaw.sin() * 0.05;
        let header = |channel_id| mcap::records::MessageHeader {
            channel_id,
            sequence: i as u32,
            log_time: t,
            publish_time: t,
        };
        let mut c = Cdr::new();
        c.header(t).string("base_link");
        c.f64s(&[x, y, 0.0, 0.0, 0.0, (yaw / 2.0).sin(), (yaw / 2.0).cos()]);
        c.f64s(&[0.0; 36])
            .f64s(&[v, 0.0, 0.0, 0.0, 0.0, wz])
            .f64s(&[0.0; 36]);
        w.write_to_known_channel(&header(odom), &c.0)?;
        let mut c = Cdr::new();
        c.header(t).f64s(&[0.0, 0.0, 0.0, 1.0]).f64s(&[0.0; 9]);
        c.f64s(&[0.0, 0.0, wz])
            .f64s(&[0.0; 9])
            .f64s(&[ax, ay, 9.8])
            .f64s(&[0.0; 9]);
        w.write_to_known_channel(&header(imu), &c.0)?;
        if i % 12_000 == 6_000 {
            w.write_to_known_channel(&header(events), &[0, 1, 0, 0])?;
        }
    }
    w.finish()?;
    Ok(())
}
