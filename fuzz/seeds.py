#!/usr/bin/env python3
"""Writes the seed corpora of the fuzz targets (run once; the minimised corpus is committed).

Seeds come from the real Bench2Drive fixtures in ../../shared/fixtures/b2d (small files and
single strings only: nothing large is copied) and from hand-made inputs in the formats of the
spec. Usage: python3 fuzz/seeds.py  (from the repository root).
"""
import hashlib
import json
import math
import os
import pathlib
import struct
import zlib

ROOT = pathlib.Path(__file__).resolve().parent
FIX = ROOT.parent.parent / "shared" / "fixtures" / "b2d"


def put(target, data):
    if isinstance(data, str):
        data = data.encode()
    d = ROOT / "corpus" / target
    d.mkdir(parents=True, exist_ok=True)
    (d / hashlib.sha1(data).hexdigest()).write_bytes(data)


def metric_info(frames, indent=4, start=1, extra=None):
    out = {}
    for i in range(frames):
        t = i * 0.05
        out[str(start + i)] = {
            "acceleration": [0.5 * math.sin(t), 0.1, 0.0],
            "angular_velocity": [0.0, 0.0, 3.0 * math.cos(t)],
            "forward_vector": [1.0, 0.0, 0.0],
            "right_vector": [0.0, 1.0, 0.0],
            "location": [1520.0 + 0.5 * i, -3310.0, 0.2],
            "rotation": [0.0, 0.0, 0.0],
            "velocity": [10.0, 0.0, 0.0],
        }
    if extra:
        out.update(extra)
    return json.dumps(out, indent=indent)


def main():
    # --- collision strings: every distinct one of the fixtures, plus edge forms.
    seen = set()
    if not FIX.is_dir():
        print(f"note: {FIX} is absent: seeds from hand-made inputs only")
    if FIX.is_dir():
        for f in sorted(FIX.glob("*.json")):
            try:
                d = json.loads(f.read_text())
            except Exception:
                continue
            for r in d.get("_checkpoint", {}).get("records", []):
                for k in ("collisions_layout", "collisions_vehicle", "collisions_pedestrian"):
                    for s in r.get("infractions", {}).get(k, []):
                        seen.add(s)
    for s in sorted(seen)[:40]:
        put("collision", s)
    for s in [
        "Agent collided against object with type=static.prop.trafficwarning and id=122",
        "Agent collided against object with type=static.prop.constructioncone",
        "Agent collided against object with type=vehicle.audi.tt and id=1 at (x=1e-05, y=-0.0, z=nan)",
        "Agent collided against object with type=walker and id=99999999999999999999 at (x=1, y=2, z=3)",
        "Agent collided against object with type= and id=1",
    ]:
        put("collision", s)

    # --- metric_info: the Bench2Drive layout, small.
    put("metric_info", metric_info(3))
    put("metric_info", metric_info(25, indent=None, start=100))
    put("metric_info", metric_info(2).replace("0.1,", "NaN,", 1))
    put("metric_info", metric_info(2).replace("3310.0", "Infinity", 1))
    put("metric_info", metric_info(2, extra={"007": {}}))
    put("metric_info", '{"7": {"acceleration": [1, 2]}}')
    put("metric_info", "{}")
    put("metric_info", "[1, 2]")
    put("metric_info", metric_info(3)[:200])

    # --- results: the small real single-route files, and hand-made variants.
    for name in ("pdmlite_route3564_endpoint_tickruntime_mesh_collisions.json",
                 "pdmlite_route24206_endpoint_crashed_empty.json"):
        p = FIX / name
        if p.is_file():
            raw = p.read_bytes()
            put("results", raw)
            put("results", raw[: len(raw) // 2])
    rec = {
        "index": 0, "route_id": "RouteScenario_900001_rep0", "status": "Completed",
        "infractions": {"collisions_layout": [], "min_speed_infractions": []},
        "scores": {"score_route": 100, "score_penalty": 1.0, "score_composed": 100.0},
        "meta": {"route_length": 120.0, "duration_game": 10.0, "duration_system": 30.0},
        "save_name": "RouteScenario_900001_rep0_Town01_DemoCruising_1_1_11_22_06_00_00",
        "town_name": "Town01", "scenario_name": "DemoCruising_1", "weather_id": "1",
    }
    bad = dict(rec, scores={"score_route": "100"})
    put("results", json.dumps({"_checkpoint": {"progress": [2, 2], "records": [rec, bad]},
                               "entry_status": "Finished"}))
    put("results", json.dumps({"_checkpoint": {"records": [rec]}, "driving score": 100.0,
                               "success rate": 1.0, "eval num": 1}))
    put("results", json.dumps({"_checkpoint": {"records": {}}}))

    # --- decode_frame: JSON lines as `sds frames` writes them.
    frames = [
        '{"a_lon":0.5,"a_lat":0.1,"a_mag":0.51,"yaw_rate":3.0,"speed":10.0,"lat_err":0.2,'
        '"collisions":{"pedestrian":0,"vehicle":0,"layout":0,"workzone":0}}',
        '{"a_lon":-6.0,"a_lat":0.0,"a_mag":6.0,"yaw_rate":0.0,"speed":8.0,"lat_err":null,'
        '"collisions":{"vehicle":1}}',
        '{"a_lon":1e-45,"a_lat":-0.0,"a_mag":3.4e38,"yaw_rate":-3.4e38,"speed":0.0}',
    ]
    put("decode_frame", "\n".join(frames * 8))
    for f in frames:
        put("decode_frame", f)
    map_seeds()


def map_seeds():
    """--- map: the hand-made OpenDRIVE maps of the map tests (a few KB each), broken ones too."""
    maps = ROOT.parent / "monitor-host" / "tests" / "data" / "maps"
    for path in sorted(maps.glob("*.xodr")):
        put("map", path.read_bytes())
    put("map", '<OpenDRIVE><road id="1" length="10" junction="-1"><planView><geometry s="0" x="0" '
               'y="0" hdg="0" length="10"><line/></geometry></planView><lanes><laneSection s="0">'
               '<right><lane id="-1" type="driving"><width sOffset="0" a="3.5" b="0" c="0" d="0"/>'
               '</lane></right></laneSection></lanes></road></OpenDRIVE>')

    # --- labels: JSON objects and CSV / TSV lines, duplicates included.
    put("labels", '{"ParkingExit": "Merging", "Accident": "Emergency braking"}')
    put("labels", '{"7": "ClearNoon", "7": "WetNoon"}')
    put("labels", "# type,family\nAccident, obstacles\n\"Hazard\",\"obstacles, static\"\n")
    put("labels", "1\tClear\n2\tRain\n1\tSun\n")
    put("labels", "=cmd|' /C calc'!A0,\u001b[2Kx\n")
    # Issue 29: bidi and invisible characters, an unclosed quote, empty labels, JSON non-labels,
    # a BOM before JSON, a label of 70,000 characters.
    put("labels", "RouteScenario_1\u202e01_rep0,hard\u2066easy\u2069\n\u200bA,\ufeffB\n")
    put("labels", "A,\"easy\nB,hard\n")
    put("labels", "A,\n,B\n")
    put("labels", '{"A": null, "B": {"x": 1}, "C": [["d"]], "D": [], "E": ""}')
    put("labels", '\ufeff{"7": ["ClearNoon", 3]}')
    put("labels", "A," + "x" * 70000 + "\n")

    # --- table: cells split at `|`, a leading digit d repeats a cell 4^d times (issue 29),
    # within 512 bytes of repeats per input (issue 34).
    put("table", "title|route|DS|RouteScenario_1\u202e01_rep0|9x|8\u2066y\u2069|\u200b\ufeff|a_b%&#$")
    put("table", "T|9" + "AB" * 10 + "|\u001b[2K\r\n\t|=HYPERLINK(\"x\")|±~^\\")

    # --- settings: NAME=VALUE lines as --set takes them.
    put("settings", "slack=0.9\nbounds.yaw_rate=1.0\ngap_max=6\n")
    put("settings", "dt=1e-45\ngap_max=-1\nalign_tie=NaN\nchunk_len=65535\n")
    put("settings", "profile=b2d-legacy\nfactors.layout=0\nnope=1\nlookahead\n")

    # --- json_keys: nested objects, duplicates at each depth.
    put("json_keys", '{"_checkpoint": {"records": [{"route_id": "a", "route_id": "b"}]}}')
    put("json_keys", '{"a": 1, "\\u0061": 2}')
    put("json_keys", "[" * 200 + "]" * 200)


# --- mcap: hand-made ROS 2 logs (records as the MCAP format defines them), issue 47.
def _rec(op, body):
    return bytes([op]) + struct.pack("<Q", len(body)) + body


def _str(s):
    b = s.encode()
    return struct.pack("<I", len(b)) + b


ODOM_DEF = ("std_msgs/Header header\nstring child_frame_id\n"
            "geometry_msgs/PoseWithCovariance pose\ngeometry_msgs/TwistWithCovariance twist\n")
IMU_DEF = ("std_msgs/Header header\ngeometry_msgs/Quaternion orientation\n"
           "float64[9] orientation_covariance\ngeometry_msgs/Vector3 angular_velocity\n"
           "float64[9] angular_velocity_covariance\ngeometry_msgs/Vector3 linear_acceleration\n"
           "float64[9] linear_acceleration_covariance\n")


def _cdr_header(t):
    # CDR_LE, stamp, frame_id "map": 16 bytes after the encapsulation, so f64s align.
    return b"\x00\x01\x00\x00" + struct.pack("<II", t // 10**9, t % 10**9) + _str("map\0")


def _odom(t, x):
    return (_cdr_header(t) + _str("base\0") + b"\x00" * 7
            + struct.pack("<7d", x, 0, 0, 0, 0, 0, 1) + struct.pack("<36d", *[0] * 36)
            + struct.pack("<6d", 5, 0, 0, 0, 0, 0) + struct.pack("<36d", *[0] * 36))


def _imu(t, ax):
    return (_cdr_header(t) + struct.pack("<4d", 0, 0, 0, 1) + struct.pack("<9d", *[0] * 9)
            + struct.pack("<3d", 0, 0, 0) + struct.pack("<9d", *[0] * 9)
            + struct.pack("<3d", ax, 0, 0) + struct.pack("<9d", *[0] * 9))


def _msg(ch, t, data):
    return _rec(0x05, struct.pack("<HIQQ", ch, 0, t, t) + data)


def _chunk(records, t0, t1, crc=True):
    c = zlib.crc32(records) if crc else 0
    return _rec(0x06, struct.pack("<QQQI", t0, t1, len(records), c) + _str("")
                + struct.pack("<Q", len(records)) + records)


def mcap_log(chunks, stray=None):
    out = b"\x89MCAP0\r\n" + _rec(0x01, _str("") + _str("seeds"))
    out += _rec(0x03, struct.pack("<H", 1) + _str("nav_msgs/msg/Odometry") + _str("ros2msg") + _str(ODOM_DEF))
    out += _rec(0x03, struct.pack("<H", 2) + _str("sensor_msgs/msg/Imu") + _str("ros2msg") + _str(IMU_DEF))
    out += _rec(0x04, struct.pack("<HH", 1, 1) + _str("/odom") + _str("cdr") + struct.pack("<I", 0))
    out += _rec(0x04, struct.pack("<HH", 2, 2) + _str("/imu") + _str("cdr") + struct.pack("<I", 0))
    if stray is not None:
        out += _msg(1, stray, _odom(stray, 0.0))
    for records, t0, t1, crc in chunks:
        out += _chunk(records, t0, t1, crc)
    out += _rec(0x0F, struct.pack("<I", 0)) + _rec(0x02, b"\x00" * 20) + b"\x89MCAP0\r\n"
    return out


def drive_chunk(second, n=6, ax=0.1, t_same=False):
    t0 = 1_700_000_000 * 10**9 + second * 10**9
    r = b""
    for i in range(n):
        t = t0 if t_same else t0 + i * 50_000_000
        r += _msg(1, t, _odom(t, 0.25 * i)) + _msg(2, t, _imu(t, ax))
    return r, t0, t0 + (n - 1) * 50_000_000


def mcap_seeds():
    good = [drive_chunk(s) + (True,) for s in range(2)]
    put("mcap", mcap_log(good))
    cut = list(good)
    cut[0] = (good[0][0][:-40],) + good[0][1:3] + (False,)
    put("mcap", mcap_log(cut))                      # a chunk ending mid-record
    zeros = list(good)
    zeros[0] = (b"\x00" * 1000,) + good[0][1:3] + (False,)
    put("mcap", mcap_log(zeros))                    # 1,000 zero bytes as the first chunk
    flipped = mcap_log(good)
    at = flipped.index(good[1][0]) + len(good[1][0]) - 96
    put("mcap", flipped[:at + 6] + b"\x20\x40" + flipped[at + 8:])   # CRC no longer holds
    put("mcap", b"\x89MCAP0\r\n" + b"\x00" * 4096)  # the magic, then zeros
    put("mcap", mcap_log(good, stray=0))            # a pose stamped 0 before the drive
    put("mcap", mcap_log([drive_chunk(0, t_same=True) + (True,)]))   # poses at one time
    put("mcap", mcap_log([drive_chunk(0) + (True,), drive_chunk(3) + (True,)]))  # a gap


def merge_part_seeds():
    put("merge_part", "{}")
    put("merge_part", '{"schema": "sds-report/1"}')
    put("merge_part", "")
    put("merge_part", "\x00" * 64)
    report = ROOT / "corpus-src" / "part.json"
    if report.exists():
        put("merge_part", report.read_bytes())


if __name__ == "__main__":
    main()
    mcap_seeds()
    merge_part_seeds()
