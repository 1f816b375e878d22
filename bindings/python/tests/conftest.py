"""Shared fixtures: the Rust `sds` binary (the reference), the demo run, the real fixtures."""

from __future__ import annotations

import json
import os
import subprocess
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any, Dict, List, Optional, Sequence, Tuple

import pytest

REPO = Path(__file__).resolve().parents[3]


@pytest.fixture(scope="session")
def sds_bin() -> Path:
    """The `sds` binary built by cargo (run-tests.sh builds it; SDS_BIN overrides)."""
    path = Path(os.environ.get("SDS_BIN", REPO / "target" / "release" / "sds"))
    if not path.exists():
        pytest.fail(f"{path} is absent: build it with `cargo build --release -p monitor-host`")
    return path


def run_cli(sds_bin: Path, args: Sequence[str]) -> Tuple[int, str, str]:
    """Runs the binary; returns (exit code, stdout, stderr)."""
    p = subprocess.run([str(sds_bin), *args], capture_output=True, text=True)
    return p.returncode, p.stdout, p.stderr


def cli_report(sds_bin: Path, args: Sequence[str], tmp: Path) -> Dict[str, Any]:
    """`sds score ARGS --format json -o FILE`, parsed (exit 0 or 3: a report was written)."""
    out = tmp / "cli-report.json"
    code, _, err = run_cli(sds_bin, ["score", *args, "--format", "json", "-o", str(out)])
    assert code in (0, 3), err
    report: Dict[str, Any] = json.loads(out.read_text())
    return report


def same(a: Any, b: Any) -> bool:
    """Equal, floats to the bit (repr is exact and tells -0.0 from 0.0)."""
    return json.dumps(a, sort_keys=True) == json.dumps(b, sort_keys=True)


def monitor_lateral(lateral: dict[str, Any]) -> dict[str, Any]:
    """A report route's `lateral` block without the host's `reference` (which polyline or map the
    host measured against: the monitor sees only the per-frame values)."""
    return {k: v for k, v in lateral.items() if k != "reference"}


def monitor_comfort(comfort: dict[str, Any]) -> dict[str, Any]:
    """A report route's `comfort` block without the host's moving comfort (`moving_chunks`,
    `moving_comfortable`, `moving_score`, docs/SCORE.md §10.0: measured by the host from positions, never by
    the monitor)."""
    return {k: v for k, v in comfort.items() if not k.startswith("moving_")}


class Demo:
    """The built-in demo run written by `sds demo`."""

    def __init__(self, root: Path) -> None:
        self.root = root
        self.results = root / "results.json"
        self.telemetry = root / "telemetry"
        self.routes = root / "routes.xml"

    def records(self) -> List[Dict[str, Any]]:
        data: Dict[str, Any] = json.loads(self.results.read_text())
        records: List[Dict[str, Any]] = data["_checkpoint"]["records"]
        return records

    def metric_info(self, save_name: str) -> List[Tuple[int, Dict[str, Any]]]:
        """(step, entry) in step order: what `get_metric_info()` returned each tick."""
        raw = json.loads((self.telemetry / save_name / "metric_info.json").read_text())
        return sorted(((int(k), v) for k, v in raw.items()), key=lambda kv: kv[0])

    def waypoints(self, route_id: str) -> List[Tuple[float, float]]:
        """The route XML's waypoints of `RouteScenario_<id>_rep<k>`."""
        xml_id = route_id.split("_")[1]
        for route in ET.parse(self.routes).getroot().iter("route"):
            if route.get("id") == xml_id:
                return [(float(p.get("x", "nan")), float(p.get("y", "nan"))) for p in route.iter("position")]
        raise KeyError(route_id)

    def frames(self, sds_bin: Path, route_id: str) -> List[Dict[str, Any]]:
        """`sds frames` of a route."""
        code, out, err = run_cli(
            sds_bin,
            ["frames", "--results", str(self.results), "--telemetry", str(self.telemetry),
             "--routes", str(self.routes), "--route-id", route_id],
        )
        assert code == 0, err
        return [json.loads(line) for line in out.splitlines()]


@pytest.fixture(scope="session")
def demo(sds_bin: Path, tmp_path_factory: pytest.TempPathFactory) -> Demo:
    root = tmp_path_factory.mktemp("demo")
    code, _, err = run_cli(sds_bin, ["demo", str(root)])
    assert code == 0, err
    return Demo(root)


@pytest.fixture(scope="session")
def demo_report(sds_bin: Path, demo: Demo, tmp_path_factory: pytest.TempPathFactory) -> Dict[str, Any]:
    return cli_report(
        sds_bin,
        ["--results", str(demo.results), "--telemetry", str(demo.telemetry), "--routes", str(demo.routes)],
        tmp_path_factory.mktemp("cli"),
    )


def fixtures_dir() -> Optional[Path]:
    d = REPO.parent / "shared" / "fixtures" / "b2d"
    return d if d.is_dir() else None


@pytest.fixture()
def b2d() -> Path:
    d = fixtures_dir()
    if d is None:
        pytest.skip(f"{REPO.parent / 'shared' / 'fixtures' / 'b2d'} is absent (real Bench2Drive fixtures)")
    return d
