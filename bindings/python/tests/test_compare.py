"""`sds.compare` against the `sds compare` binary: the same report, the errors' classes."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Dict

import pytest

import sds

from conftest import run_cli


def _demo(sds_bin: Path, tmp: Path) -> Path:
    code, _, err = run_cli(sds_bin, ["demo", str(tmp / "demo")])
    assert code == 0, err
    return tmp / "demo"


def test_compare_is_the_cli_report(sds_bin: Path, tmp_path: Path) -> None:
    demo = _demo(sds_bin, tmp_path)
    res, tel = demo / "results.json", demo / "telemetry"
    c = sds.compare(
        {"a": (res, tel), "b": (str(res), str(tel))}, bootstrap_samples=500, bootstrap_seed=3
    )
    assert c["schema"] == "sds-compare/1"
    assert c["baseline"] == "a"
    out = tmp_path / "cli.json"
    code, _, err = run_cli(
        sds_bin,
        ["compare", f"a={res}:{tel}", f"b={res}:{tel}", "--bootstrap-samples", "500",
         "--bootstrap-seed", "3", "--format", "json", "-o", str(out)],
    )
    assert code == 0, err
    cli: Dict[str, Any] = json.loads(out.read_text())
    assert c == cli
    ds = [p for p in c["paired"] if p["model"] == "b" and p["metric"] == "ds"][0]
    assert ds["delta"] == 0.0 and ds["verdict"] == "within noise"


def test_seeds_and_errors(sds_bin: Path, tmp_path: Path) -> None:
    demo = _demo(sds_bin, tmp_path)
    res, tel = demo / "results.json", demo / "telemetry"
    c = sds.compare(
        {"base": (res, tel), "s1": (res, tel), "s2": (res, tel)},
        seeds={"m": ["s1", "s2"]},
        bootstrap_samples=100,
    )
    assert [m["name"] for m in c["models"]] == ["base", "m"]
    assert c["models"][1]["runs"] == ["s1", "s2"]
    with pytest.raises(sds.ConfigError, match="needs at least two models"):
        sds.compare({"a": (res, tel)})
    with pytest.raises(sds.ConfigError, match="unknown metric"):
        sds.compare({"a": (res, tel), "b": (res, tel)}, fail_if_worse=["nope"])
    with pytest.raises(sds.IoError, match="run b: .*absent.json"):
        sds.compare({"a": (res, tel), "b": (tmp_path / "absent.json", tel)})


def test_shared_options_are_the_cli_flags(sds_bin: Path, tmp_path: Path) -> None:
    """The keyword arguments sds.score shares (RunKwargs) map to the same settings as the flags
    `sds compare` shares with `sds score` (RunArgs)."""
    demo = _demo(sds_bin, tmp_path)
    res, tel = demo / "results.json", demo / "telemetry"
    c = sds.compare(
        {"a": (res, tel), "b": (res, tel)},
        routes=demo / "routes.xml",
        profile="b2d-legacy",
        allow_missing_telemetry=True,
        settings={"slack": 0.9},
        protocols=["lb2.1"],
        jobs=1,
        bootstrap_samples=200,
    )
    out = tmp_path / "cli.json"
    code, _, err = run_cli(
        sds_bin,
        ["compare", f"a={res}:{tel}", f"b={res}:{tel}", "--routes", str(demo / "routes.xml"),
         "--profile", "b2d-legacy", "--allow-missing-telemetry", "--set", "slack=0.9",
         "--protocol", "lb2.1", "--jobs", "1", "--bootstrap-samples", "200",
         "--format", "json", "-o", str(out)],
    )
    assert code == 0, err
    assert c == json.loads(out.read_text())
    with pytest.raises(sds.ConfigError, match="protocols"):
        sds.compare({"a": (res, tel), "b": (res, tel)}, protocols="lb2.1")
    with pytest.raises(sds.ConfigError, match="profile=\"fast\""):
        sds.compare({"a": (res, tel), "b": (res, tel)}, profile="fast")
