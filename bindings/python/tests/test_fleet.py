"""A fleet's vehicle logs on Ray (issue 51 goal 3): 20 MCAP logs, written by the project's own
writer (scripts/fleet_logs.py: the demo's routes through scripts/telemetry_to_mcap.py), scored
by ``sds.fleet.score_logs_on_ray`` on a local cluster of 2 CPUs in batches of 6 (4 tasks, the
last of 2 logs); the merged report equals ``sds score`` over the 20 logs on one machine but for
``inputs`` and ``warnings``. Skips, saying why, without Ray or the MCAP writer's packages."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any, Dict

import pytest

from conftest import REPO

ray = pytest.importorskip(
    "ray",
    reason="ray is not installed in the test venv (scripts/setup.sh downloads ray==2.60.0 into "
    "the wheelhouse; no wheel for this platform or Python?): the fleet test skips",
)
pytest.importorskip(
    "mcap_ros2.writer",
    reason="mcap-ros2-support is not installed in the test venv (scripts/setup.sh puts mcap and "
    "mcap-ros2-support in the wheelhouse; run-tests.sh installs them): the fleet test skips",
)

import sds.fleet  # noqa: E402

TOPICS = ["path=/path", "event=/events"]


def _without(report: Dict[str, Any], *keys: str) -> Dict[str, Any]:
    return {k: v for k, v in report.items() if k not in keys}


def test_fleet_of_20_logs_on_ray_merges_to_the_one_machine_score(
    sds_bin: Path, tmp_path: Path
) -> None:
    logs_dir = tmp_path / "logs"
    subprocess.run(
        [sys.executable, str(REPO / "scripts" / "fleet_logs.py"), str(sds_bin), str(logs_dir), "20"],
        check=True,
        capture_output=True,
    )
    logs = sorted(logs_dir.glob("*.mcap"))
    assert len(logs) == 20
    # Ray's sockets live under its temp folder, and a Unix socket path holds at most 107 bytes:
    # a short folder of its own, not pytest's deep one.
    ray_tmp = tempfile.mkdtemp(prefix="sds-ray-")
    ray.init(
        num_cpus=2,
        include_dashboard=False,
        log_to_driver=False,
        object_store_memory=80 * 1024 * 1024,
        _temp_dir=ray_tmp,
    )
    try:
        # The tasks run the package's own `python -m sds` (no sds_bin): what a worker with only
        # the wheel installed has.
        run = sds.fleet.score_logs_on_ray(
            logs, tmp_path / "parts", batch=6, topics=TOPICS, timeout=600
        )
    finally:
        ray.shutdown()
        shutil.rmtree(ray_tmp, ignore_errors=True)

    assert [len(p.inputs) for p in run.parts] == [6, 6, 6, 2]
    assert [p.inputs for p in run.parts] == [tuple(logs[i : i + 6]) for i in range(0, 20, 6)]
    assert all(p.peak_rss_kib > 0 and p.output.is_file() for p in run.parts)
    assert run.merge.peak_rss_kib > 0 and run.merge.inputs == tuple(p.output for p in run.parts)

    whole_file = tmp_path / "whole.json"
    args = ["score"] + [a for log in logs for a in ("--mcap", str(log))]
    args += [a for t in TOPICS for a in ("--topic", t)]
    done = subprocess.run(
        [str(sds_bin), *args, "--format", "json", "--output", str(whole_file)],
        capture_output=True,
        text=True,
    )
    assert done.returncode in (0, 3), done.stderr
    whole = json.loads(whole_file.read_text())
    merged = run.report
    assert merged == json.loads((tmp_path / "parts" / "merged.json").read_text())
    # What legitimately differs: `inputs` (the parts and their digests, against the logs') and
    # `warnings` (each part's, prefixed by the part).
    assert _without(merged, "inputs", "warnings") == _without(whole, "inputs", "warnings")
    assert [r["route_id"] for r in merged["routes"]] == [log.stem for log in logs]
    assert merged["summary"]["routes"] == 20
    # Vehicle logs carry no Leaderboard figure, merged or not; the events survive the merge.
    assert merged["summary"]["driving_score"] is None
    assert merged["summary"]["invalid_records"] == 0
    assert sum(r["infractions"]["collisions_vehicle"] for r in merged["routes"]) > 0
    assert [Path(p["file"]) for p in merged["inputs"]["parts"]] == [p.output for p in run.parts]


def test_fleet_batches_refuse_a_zero_size() -> None:
    with pytest.raises(ValueError, match="at least 1 log"):
        sds.fleet.batches([Path("a.mcap")], 0)
    assert sds.fleet.batches([Path(f"{i}.mcap") for i in range(5)], 2) == [
        [Path("0.mcap"), Path("1.mcap")],
        [Path("2.mcap"), Path("3.mcap")],
        [Path("4.mcap")],
    ]
