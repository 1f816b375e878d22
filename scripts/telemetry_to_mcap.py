#!/usr/bin/env python3
"""Writes a Bench2Drive route's telemetry (metric_info.json) as a ROS 2 MCAP log.

An independent writer (the `mcap` and `mcap-ros2-support` packages, not this project's code) for
checking `sds score --mcap` against the telemetry itself (docs/SCORE.md §2.4), and for trying the
vehicle-log path on CARLA runs.

CARLA's world is left-handed (y to the right), ROS's right-handed (REP 103: y to the left), so
the log is CARLA mirrored in y, as the CARLA ROS bridge writes it: position (x, -y), yaw -psi,
body acceleration (forward, left) = (a . forward, -(a . right)), yaw rate -omega in rad/s.

Usage: telemetry_to_mcap.py METRIC_INFO OUT.mcap --dt 0.05 [--path X,Y,Z;...] [--events STEP,...]
  --dt      the telemetry's step period (s): message log times are (step - first) * dt
  --path    the route's waypoints (CARLA x, y, z), written once as nav_msgs/msg/Path on /path
  --events  telemetry steps at which to write a std_msgs/msg/Empty on /events
  --chunk   MCAP chunk size in bytes (default 1 MiB)
  --compression  chunk compression: zstd (default, as the mcap package writes), lz4 or none
"""

import argparse
import json
import math

from mcap_ros2.writer import Writer

SEP = "=" * 80 + "\n"
TIME = "MSG: builtin_interfaces/Time\nint32 sec\nuint32 nanosec\n"
HEADER = "MSG: std_msgs/Header\nbuiltin_interfaces/Time stamp\nstring frame_id\n"
POINT = "MSG: geometry_msgs/Point\nfloat64 x\nfloat64 y\nfloat64 z\n"
QUAT = "MSG: geometry_msgs/Quaternion\nfloat64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1\n"
VEC3 = "MSG: geometry_msgs/Vector3\nfloat64 x\nfloat64 y\nfloat64 z\n"
POSE = "MSG: geometry_msgs/Pose\nPoint position\nQuaternion orientation\n"
TWIST = "MSG: geometry_msgs/Twist\nVector3 linear\nVector3 angular\n"


def msgdef(top, *subs):
    return top + "".join(SEP + s for s in subs)


ODOMETRY = msgdef(
    "std_msgs/Header header\nstring child_frame_id\n"
    "geometry_msgs/PoseWithCovariance pose\ngeometry_msgs/TwistWithCovariance twist\n",
    HEADER, TIME,
    "MSG: geometry_msgs/PoseWithCovariance\nPose pose\nfloat64[36] covariance\n",
    POSE, POINT, QUAT,
    "MSG: geometry_msgs/TwistWithCovariance\nTwist twist\nfloat64[36] covariance\n",
    TWIST, VEC3,
)
IMU = msgdef(
    "std_msgs/Header header\ngeometry_msgs/Quaternion orientation\n"
    "float64[9] orientation_covariance\ngeometry_msgs/Vector3 angular_velocity\n"
    "float64[9] angular_velocity_covariance\ngeometry_msgs/Vector3 linear_acceleration\n"
    "float64[9] linear_acceleration_covariance\n",
    HEADER, TIME, QUAT, VEC3,
)
PATH = msgdef(
    "std_msgs/Header header\ngeometry_msgs/PoseStamped[] poses\n",
    HEADER, TIME,
    "MSG: geometry_msgs/PoseStamped\nstd_msgs/Header header\nPose pose\n",
    POSE, POINT, QUAT,
)


def header(ns, frame="map"):
    return {"stamp": {"sec": ns // 10**9, "nanosec": ns % 10**9}, "frame_id": frame}


def quat(yaw):
    return {"x": 0.0, "y": 0.0, "z": math.sin(yaw / 2), "w": math.cos(yaw / 2)}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("metric_info")
    ap.add_argument("out")
    ap.add_argument("--dt", type=float, required=True)
    ap.add_argument("--path", default="")
    ap.add_argument("--events", default="")
    ap.add_argument("--chunk", type=int, default=1 << 20)
    ap.add_argument("--compression", choices=["zstd", "lz4", "none"], default="zstd")
    ap.add_argument("--base-ns", type=int, default=1_700_000_000 * 10**9)
    a = ap.parse_args()

    with open(a.metric_info) as f:
        tel = json.load(f)
    steps = sorted(int(k) for k in tel)
    first = steps[0]
    dt_ns = round(a.dt * 1e9)

    def t_of(step):
        return a.base_ns + (step - first) * dt_ns

    with open(a.out, "wb") as f:
        from mcap.writer import CompressionType

        kind = {"zstd": CompressionType.ZSTD, "lz4": CompressionType.LZ4,
                "none": CompressionType.NONE}[a.compression]
        w = Writer(f, chunk_size=a.chunk, compression=kind)
        odom = w.register_msgdef("nav_msgs/msg/Odometry", ODOMETRY)
        imu = w.register_msgdef("sensor_msgs/msg/Imu", IMU)
        zeros9, zeros36 = [0.0] * 9, [0.0] * 36
        if a.path:
            path = w.register_msgdef("nav_msgs/msg/Path", PATH)
            pts = [tuple(float(v) for v in p.split(",")) for p in a.path.split(";")]
            poses = [
                {"header": header(a.base_ns),
                 "pose": {"position": {"x": x, "y": -y, "z": z}, "orientation": quat(0.0)}}
                for x, y, z in pts
            ]
            w.write_message("/path", path, {"header": header(a.base_ns), "poses": poses},
                            log_time=a.base_ns, publish_time=a.base_ns)
        for i, step in enumerate(steps):
            fr = tel[str(step)]
            ns = t_of(step)
            acc, fwd, right = fr["acceleration"], fr["forward_vector"], fr["right_vector"]
            x, y, z = fr["location"]
            psi = math.atan2(fwd[1], fwd[0])  # CARLA yaw (its left-handed frame)
            a_fwd = acc[0] * math.cos(psi) + acc[1] * math.sin(psi)
            a_right = -acc[0] * math.sin(psi) + acc[1] * math.cos(psi)
            omega = math.radians(fr["angular_velocity"][2])
            w.write_message("/odom", odom, {
                "header": header(ns), "child_frame_id": "base_link",
                "pose": {"pose": {"position": {"x": x, "y": -y, "z": z},
                                  "orientation": quat(-psi)}, "covariance": zeros36},
                "twist": {"twist": {"linear": {"x": 0.0, "y": 0.0, "z": 0.0},
                                    "angular": {"x": 0.0, "y": 0.0, "z": -omega}},
                          "covariance": zeros36},
            }, log_time=ns, publish_time=ns, sequence=i)
            w.write_message("/imu", imu, {
                "header": header(ns, "base_link"), "orientation": quat(-psi),
                "orientation_covariance": zeros9,
                "angular_velocity": {"x": 0.0, "y": 0.0, "z": -omega},
                "angular_velocity_covariance": zeros9,
                "linear_acceleration": {"x": a_fwd, "y": -a_right, "z": 0.0},
                "linear_acceleration_covariance": zeros9,
            }, log_time=ns, publish_time=ns, sequence=i)
        if a.events:
            empty = w.register_msgdef("std_msgs/msg/Empty", "")
            for s in a.events.split(","):
                ns = t_of(int(s))
                w.write_message("/events", empty, {}, log_time=ns, publish_time=ns)
        w.finish()


if __name__ == "__main__":
    main()
