//! The ROS 2 message types a vehicle log is read from (docs/SCORE.md §2.4): their names, the
//! definitions the reader was written for (checked against the ones embedded in the log's
//! schemas), and their CDR decoding into the few values the frames need.

use super::cdr::{Cdr, CdrError};

/// A message type the reader knows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RosType {
    /// `nav_msgs/msg/Odometry`: pose and body twist.
    Odometry,
    /// `geometry_msgs/msg/PoseStamped`: pose only.
    PoseStamped,
    /// `sensor_msgs/msg/Imu`: body-frame acceleration and angular velocity.
    Imu,
    /// `nav_msgs/msg/Path`: the reference path.
    Path,
}

impl RosType {
    /// The schema name as rosbag2 writes it (`nav_msgs/msg/Odometry`).
    pub fn name(self) -> &'static str {
        match self {
            RosType::Odometry => "nav_msgs/msg/Odometry",
            RosType::PoseStamped => "geometry_msgs/msg/PoseStamped",
            RosType::Imu => "sensor_msgs/msg/Imu",
            RosType::Path => "nav_msgs/msg/Path",
        }
    }

    /// The type named `schema` (ROS 1 style `nav_msgs/Odometry` is accepted too).
    ///
    /// ```
    /// use monitor_host::input::mcap::messages::RosType;
    /// assert_eq!(RosType::of("nav_msgs/msg/Odometry"), Some(RosType::Odometry));
    /// assert_eq!(RosType::of("nav_msgs/Path"), Some(RosType::Path));
    /// assert_eq!(RosType::of("sensor_msgs/msg/NavSatFix"), None);
    /// ```
    pub fn of(schema: &str) -> Option<RosType> {
        [
            RosType::Odometry,
            RosType::PoseStamped,
            RosType::Imu,
            RosType::Path,
        ]
        .into_iter()
        .find(|t| t.name() == schema || t.name().replacen("/msg/", "/", 1) == schema)
    }
}

/// The fields (type, name) of each message definition the decoders read, with package
/// prefixes dropped: a log whose embedded definitions differ is refused.
const DEFINITIONS: &[(&str, &[(&str, &str)])] = &[
    (
        "Odometry",
        &[
            ("Header", "header"),
            ("string", "child_frame_id"),
            ("PoseWithCovariance", "pose"),
            ("TwistWithCovariance", "twist"),
        ],
    ),
    ("PoseStamped", &[("Header", "header"), ("Pose", "pose")]),
    (
        "Imu",
        &[
            ("Header", "header"),
            ("Quaternion", "orientation"),
            ("float64[9]", "orientation_covariance"),
            ("Vector3", "angular_velocity"),
            ("float64[9]", "angular_velocity_covariance"),
            ("Vector3", "linear_acceleration"),
            ("float64[9]", "linear_acceleration_covariance"),
        ],
    ),
    ("Path", &[("Header", "header"), ("PoseStamped[]", "poses")]),
    ("Header", &[("Time", "stamp"), ("string", "frame_id")]),
    ("Time", &[("int32", "sec"), ("uint32", "nanosec")]),
    (
        "PoseWithCovariance",
        &[("Pose", "pose"), ("float64[36]", "covariance")],
    ),
    (
        "TwistWithCovariance",
        &[("Twist", "twist"), ("float64[36]", "covariance")],
    ),
    (
        "Pose",
        &[("Point", "position"), ("Quaternion", "orientation")],
    ),
    ("Twist", &[("Vector3", "linear"), ("Vector3", "angular")]),
    (
        "Point",
        &[("float64", "x"), ("float64", "y"), ("float64", "z")],
    ),
    (
        "Vector3",
        &[("float64", "x"), ("float64", "y"), ("float64", "z")],
    ),
    (
        "Quaternion",
        &[
            ("float64", "x"),
            ("float64", "y"),
            ("float64", "z"),
            ("float64", "w"),
        ],
    ),
];

/// `std_msgs/msg/Header` → `Header`, keeping an array suffix.
fn short(t: &str) -> &str {
    t.rsplit('/').next().unwrap_or(t)
}

/// The (type, name) fields of one `.msg` text: comments, blank lines and constants dropped,
/// default values ignored.
fn fields(text: &str) -> Vec<(String, String)> {
    text.lines()
        .map(|l| l.split('#').next().unwrap_or_default().trim())
        .filter(|l| !l.is_empty() && !l.contains('='))
        .filter_map(|l| {
            let mut it = l.split_whitespace();
            Some((short(it.next()?).to_string(), it.next()?.to_string()))
        })
        .collect()
}

/// Checks a `ros2msg` schema (the type's definition, then `MSG: pkg/Type` sections of the types
/// it uses) against the definitions the decoders read. An empty schema (older rosbag2) is
/// taken by its name alone. Returns what differs: the section's type and both field lists.
///
/// ```
/// use monitor_host::input::mcap::messages::{check_definition, RosType};
/// let ok = "std_msgs/Header header\ngeometry_msgs/Pose pose\n";
/// assert!(check_definition(RosType::PoseStamped, "ros2msg", ok).is_ok());
/// let bad = "std_msgs/Header header\ngeometry_msgs/Point pose\n";
/// assert!(check_definition(RosType::PoseStamped, "ros2msg", bad).unwrap_err().contains("Point pose"));
/// ```
///
/// # Errors
/// A sentence naming the section whose fields differ, with the expected and the found fields.
pub fn check_definition(t: RosType, encoding: &str, text: &str) -> Result<(), String> {
    if encoding != "ros2msg" || text.trim().is_empty() {
        // ros2idl definitions are taken by name (the IDL's field lists are not parsed).
        return Ok(());
    }
    let mut sections = vec![(short(t.name()).to_string(), String::new())];
    for line in text.lines() {
        if line.starts_with("====") {
            continue;
        }
        if let Some(name) = line.strip_prefix("MSG: ") {
            sections.push((short(name.trim()).to_string(), String::new()));
        } else if let Some((_, body)) = sections.last_mut() {
            body.push_str(line);
            body.push('\n');
        }
    }
    for (name, body) in &sections {
        let Some((_, want)) = DEFINITIONS.iter().find(|(n, _)| n == name) else {
            continue;
        };
        let found = fields(body);
        let want: Vec<(String, String)> = want
            .iter()
            .map(|(a, b)| (a.to_string(), b.to_string()))
            .collect();
        if found != want {
            let show = |f: &[(String, String)]| {
                f.iter()
                    .map(|(t, n)| format!("{t} {n}"))
                    .collect::<Vec<_>>()
                    .join("; ")
            };
            return Err(format!(
                "its definition of {name} has fields [{}], the reader expects [{}]",
                show(&found),
                show(&want)
            ));
        }
    }
    Ok(())
}

/// A pose message's values: position and yaw, and the body twist of an odometry message.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PoseMsg {
    /// Position x, y, z (m).
    pub position: [f64; 3],
    /// Orientation quaternion x, y, z, w.
    pub orientation: [f64; 4],
    /// Body twist: linear x, y (m/s) and angular z (rad/s); `None` for `PoseStamped`.
    pub twist: Option<[f64; 3]>,
}

/// An IMU message's values (body frame).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImuMsg {
    /// Linear acceleration x (forward), y (left) in m/s².
    pub acc: [f64; 2],
    /// Angular velocity z (rad/s).
    pub yaw_rate: f64,
}

fn header(c: &mut Cdr<'_>) -> Result<(), CdrError> {
    c.i32()?;
    c.u32()?;
    c.string()?;
    Ok(())
}

fn pose(c: &mut Cdr<'_>) -> Result<([f64; 3], [f64; 4]), CdrError> {
    Ok((c.f64s::<3>()?, c.f64s::<4>()?))
}

/// Decodes a pose message of type `t` (`Odometry` or `PoseStamped`).
///
/// # Errors
/// [`CdrError`]: the bytes are not this type's CDR.
pub fn decode_pose(t: RosType, data: &[u8]) -> Result<PoseMsg, CdrError> {
    let mut c = Cdr::new(data)?;
    header(&mut c)?;
    if t == RosType::Odometry {
        c.string()?;
    }
    let (position, orientation) = pose(&mut c)?;
    let twist = if t == RosType::Odometry {
        c.f64s::<36>()?;
        let linear = c.f64s::<3>()?;
        let angular = c.f64s::<3>()?;
        Some([linear[0], linear[1], angular[2]])
    } else {
        None
    };
    Ok(PoseMsg {
        position,
        orientation,
        twist,
    })
}

/// Decodes a `sensor_msgs/msg/Imu`.
///
/// # Errors
/// [`CdrError`]: the bytes are not an Imu's CDR.
pub fn decode_imu(data: &[u8]) -> Result<ImuMsg, CdrError> {
    let mut c = Cdr::new(data)?;
    header(&mut c)?;
    c.f64s::<4>()?;
    c.f64s::<9>()?;
    let w = c.f64s::<3>()?;
    c.f64s::<9>()?;
    let a = c.f64s::<3>()?;
    c.f64s::<9>()?;
    Ok(ImuMsg {
        acc: [a[0], a[1]],
        yaw_rate: w[2],
    })
}

/// Decodes a `nav_msgs/msg/Path`: its poses' positions (x, y, z).
///
/// # Errors
/// [`CdrError`]: the bytes are not a Path's CDR.
pub fn decode_path(data: &[u8]) -> Result<Vec<[f64; 3]>, CdrError> {
    let mut c = Cdr::new(data)?;
    header(&mut c)?;
    // Each PoseStamped holds at least a header (12 bytes) and 7 f64.
    let n = c.sequence_len(12 + 56)?;
    let mut out = Vec::with_capacity(n);
    for _ in 0..n {
        header(&mut c)?;
        out.push(pose(&mut c)?.0);
    }
    Ok(out)
}

/// The yaw (rad) of a quaternion x, y, z, w: the rotation about z.
///
/// ```
/// let h = std::f64::consts::FRAC_1_SQRT_2;
/// let yaw = monitor_host::input::mcap::messages::yaw([0.0, 0.0, h, h]);
/// assert!((yaw - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
/// ```
pub fn yaw(q: [f64; 4]) -> f64 {
    let [x, y, z, w] = q;
    f64::atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))
}
