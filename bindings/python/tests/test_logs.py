"""Issue 48 item 1: Python scores vehicle logs (`sds.score(mcap=[...])`) and reads a route's
frames (`sds.frames`), through the library's requests, equal to `sds score --mcap` and `sds
frames`."""

from __future__ import annotations

import json
import os
import subprocess
from pathlib import Path
from typing import Any, Dict, List

import pytest

import sds
from conftest import REPO, Demo, cli_report, run_cli, same

ROUTE = "RouteScenario_900001_rep0"


def writer_python() -> Path:
    """The tools' Python with `mcap` and `mcap-ros2-support` (scripts/setup.sh), or a skip."""
    target = Path(os.environ.get("CARGO_TARGET_DIR", REPO / "target"))
    py = target / "py-tools" / "bin" / "python"
    ok = py.exists() and subprocess.run([str(py), "-c", "import mcap_ros2.writer"]).returncode == 0
    if not ok:
        pytest.skip(f"{py} cannot import mcap_ros2 (scripts/setup.sh installs it): no log to write")
    return py


@pytest.fixture(scope="module")
def log(demo: Demo, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The demo route's telemetry as a ROS 2 log, by the independent writer."""
    py = writer_python()
    folder = next(p for p in demo.telemetry.iterdir() if p.name.startswith(ROUTE + "_"))
    out = tmp_path_factory.mktemp("logs") / f"{ROUTE}.mcap"
    p = subprocess.run(
        [str(py), str(REPO / "scripts" / "telemetry_to_mcap.py"), str(folder / "metric_info.json"),
         str(out), "--dt", "0.05"],
        capture_output=True, text=True,
    )
    assert p.returncode == 0, p.stderr
    return out


def cli_frames(sds_bin: Path, args: List[str]) -> List[Dict[str, Any]]:
    code, out, err = run_cli(sds_bin, ["frames", *args])
    assert code == 0, err
    return [json.loads(line) for line in out.splitlines()]


def test_i48_1_score_mcap_equals_cli(sds_bin: Path, log: Path, tmp_path: Path) -> None:
    with pytest.warns(sds.SdsWarning, match="no Leaderboard record"):
        report = sds.score(mcap=[log], profile="autoware")
    expected = cli_report(sds_bin, ["--mcap", str(log), "--profile", "autoware"], tmp_path)
    assert report["routes"][0]["route_id"] == ROUTE
    assert report["summary"]["driving_score"] is None
    assert report["routes"][0]["frames"] > 0
    assert same(report, expected)


def test_i48_1_frames_of_a_log_and_of_a_route_equal_cli(sds_bin: Path, demo: Demo, log: Path) -> None:
    got = sds.frames(mcap=log, topics=["pose=/odom", "imu=/imu"])
    assert got and got == cli_frames(sds_bin, ["--mcap", str(log), "--topic", "pose=/odom", "--topic", "imu=/imu"])
    route = sds.frames(demo.results, route_id=ROUTE, telemetry=demo.telemetry, routes=demo.routes)
    assert route == demo.frames(sds_bin, ROUTE)
    assert route[0]["host"]["step"] is not None


def test_i48_1_frames_settings_change_the_frames(sds_bin: Path, demo: Demo) -> None:
    args = dict(route_id=ROUTE, telemetry=demo.telemetry, routes=demo.routes)
    coarse = sds.frames(demo.results, settings={"dt": 0.1}, **args)  # type: ignore[arg-type]
    assert {f["host"]["dt"] for f in coarse} == {0.1}
    assert coarse == cli_frames(
        sds_bin, ["--results", str(demo.results), "--telemetry", str(demo.telemetry), "--routes",
                  str(demo.routes), "--route-id", ROUTE, "--set", "dt=0.1"])


def test_i48_1_log_options_refused_as_the_cli_refuses(demo: Demo, log: Path) -> None:
    with pytest.raises(sds.ConfigError, match="names a vehicle log's topic, but no log is given"):
        sds.score(demo.results, topics=["pose=/odom"])
    with pytest.raises(sds.ConfigError, match="scored apart"):
        sds.score(demo.results, mcap=[log])
    with pytest.raises(sds.ConfigError, match="pose"):
        sds.score(mcap=[log], topics=["pose=/a", "pose=/b"])
    with pytest.raises(sds.ConfigError, match="names a vehicle log's topic"):
        sds.frames(demo.results, route_id=ROUTE, topics=["pose=/odom"])
    with pytest.raises(sds.ConfigError, match="expected a list"):
        sds.frames(mcap=log, topics="pose=/odom")  # type: ignore[arg-type]
    with pytest.raises(sds.InputError):
        sds.frames(demo.results, route_id="RouteScenario_1_rep0", telemetry=demo.telemetry)


def test_i48_1_link_plays_vehicle_logs(sds_bin: Path, demo: Demo, log: Path, tmp_path: Path) -> None:
    """`sds.link(mcap=[...])` plays a vehicle log to the checker as `sds link --mcap` does (the
    same report but the exchange's wall-clock latencies), its topics as given."""
    checker = f"exec:{sds_bin} checker"
    got = sds.link(mcap=[log], topics=["pose=/odom", "imu=/imu"], to=checker, profile="autoware")
    out = tmp_path / "link.json"
    code, _, err = run_cli(
        sds_bin,
        ["link", "--mcap", str(log), "--topic", "pose=/odom", "--topic", "imu=/imu", "--to", checker,
         "--profile", "autoware", "-o", str(out)],
    )
    assert code == 0, err
    expected = json.loads(out.read_text())
    for r in (got, expected):
        for route in r["routes"]:
            route["link"].pop("latency_ms")
    assert got == expected
    assert [r["route_id"] for r in got["routes"]] == [ROUTE]
    assert got["routes"][0]["frames"] > 0 and got["summary"]["equal_routes"] == 1
    # The log's frames are the ones `sds.frames` reads from it.
    assert got["routes"][0]["frames"] == len(sds.frames(mcap=log))
    with pytest.raises(sds.ConfigError, match="played apart"):
        sds.link(demo.results, mcap=[log], to=checker)
    with pytest.raises(sds.ConfigError, match="names a vehicle log's topic"):
        sds.link(demo.results, telemetry=demo.telemetry, topics=["pose=/odom"], to=checker)
