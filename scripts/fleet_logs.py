#!/usr/bin/env python3
"""Writes N vehicle logs (MCAP) for the fleet test and benchmark, from the demo run.

`sds demo` writes nine routes' telemetry; each is written once as a ROS 2 MCAP log by the
project's own writer (scripts/telemetry_to_mcap.py: its step period, the route XML's waypoints
on /path, its collision steps on /events), and the N logs are hard links to those nine, named
drive-00000.mcap, drive-00001.mcap, ... (a log is one route named by its file stem, so every
name is a route of its own). Hard links: 2,000 logs cost nine files' bytes.

Usage: fleet_logs.py SDS_BIN OUT_DIR N
Needs the `mcap` and `mcap-ros2-support` packages in the Python that runs it.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Dict, List

WRITER = Path(__file__).resolve().parent / "telemetry_to_mcap.py"

# The topics the written logs use beyond the default pose=/odom and imu=/imu.
TOPICS = ["path=/path", "event=/events"]


def _waypoints(routes_xml: Path) -> Dict[str, str]:
    """Each route XML id's waypoints as the writer's --path argument."""
    out = {}
    for route in ET.parse(routes_xml).getroot().iter("route"):
        points = [
            f"{p.get('x')},{p.get('y')},{p.get('z')}" for p in route.iter("position")
        ]
        out[route.get("id", "")] = ";".join(points)
    return out


def base_logs(sds: str, work: Path) -> List[Path]:
    """The demo's routes, one MCAP log each, in `work`."""
    demo = work / "demo"
    subprocess.run([sds, "demo", str(demo)], check=True, stdout=subprocess.DEVNULL)
    scored = subprocess.run(
        [sds, "score", "--results", str(demo / "results.json"), "--telemetry",
         str(demo / "telemetry"), "--routes", str(demo / "routes.xml"), "--format", "json"],
        check=False, capture_output=True,
    )
    # Exit 3 is a problem route (the demo has some on purpose); the report is written.
    if scored.returncode not in (0, 3):
        sys.exit(f"fleet_logs: sds score of the demo failed: {scored.stderr.decode()}")
    report = json.loads(scored.stdout)
    paths = _waypoints(demo / "routes.xml")
    folders = {p.name.split("_rep")[0] + "_rep0": p for p in (demo / "telemetry").iterdir()}
    logs = []
    for route in report["routes"]:
        rid = route["route_id"]
        xml_id = rid.removeprefix("RouteScenario_").split("_rep")[0]
        log = work / f"{rid}.mcap"
        cmd = [sys.executable, str(WRITER), str(folders[rid] / "metric_info.json"), str(log),
               "--dt", str(route["dt"]), "--path", paths[xml_id]]
        steps = [str(e["step"]) for e in route["collision_events"] if e.get("step") is not None]
        if steps:
            cmd += ["--events", ",".join(steps)]
        subprocess.run(cmd, check=True)
        logs.append(log)
    return logs


def write_logs(sds: str, out: Path, n: int) -> List[Path]:
    """`n` logs in `out` (drive-00000.mcap, ...), hard links to the demo's nine."""
    out.mkdir(parents=True, exist_ok=True)
    base_dir = out / ".base"
    base_dir.mkdir(exist_ok=True)
    base = base_logs(sds, Path(tempfile.mkdtemp(dir=base_dir)))
    logs = []
    for i in range(n):
        log = out / f"drive-{i:05d}.mcap"
        if log.exists():
            log.unlink()
        os.link(base[i % len(base)], log)
        logs.append(log)
    return logs


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    written = write_logs(sys.argv[1], Path(sys.argv[2]), int(sys.argv[3]))
    print(f"fleet_logs: wrote {len(written)} logs to {sys.argv[2]}")
