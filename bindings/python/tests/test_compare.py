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
