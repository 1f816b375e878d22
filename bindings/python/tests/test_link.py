"""`sds.link`: the demo run played to the host checker (`sds checker`) through the library
(issue 49); the same report as `sds link`."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Dict

import pytest

import sds
from conftest import Demo, run_cli


def test_link_to_host_checker_is_equal_on_every_route(sds_bin: Path, demo: Demo, tmp_path: Path) -> None:
    report = sds.link(
        demo.results,
        telemetry=demo.telemetry,
        to=f"exec:{sds_bin} checker",
        inject="drop=0.05,corrupt=0.05,seed=3",
        tap=tmp_path / "tap",
    )
    assert report["summary"]["routes"] >= 5
    assert report["summary"]["equal_routes"] == report["summary"]["routes"]
    assert all(r["link"]["equal"] for r in report["routes"])
    assert (tmp_path / "tap" / "sent.bin").stat().st_size > 0


def test_link_bad_target_is_a_config_error(demo: Demo) -> None:
    with pytest.raises(sds.ConfigError, match="tcp:HOST:PORT"):
        sds.link(demo.results, telemetry=demo.telemetry, to="udp:x")


def test_link_settings_reach_the_doer(sds_bin: Path, demo: Demo) -> None:
    """`link.*` settings are read by the library, not the command line: with `link.max_delta=1`
    on both sides, a lost frame is WRONGSEQUENCE (not OKSOMELOST) and every route is still equal
    (the doer's own judgement used the same setting as the checker)."""
    drops = "drop=0.05,seed=7"
    default = sds.link(demo.results, telemetry=demo.telemetry, to=f"exec:{sds_bin} checker", inject=drops)
    strict = sds.link(
        demo.results,
        telemetry=demo.telemetry,
        to=f"exec:{sds_bin} checker --set link.max_delta=1",
        inject=drops,
        settings={"link.max_delta": 1},
    )

    def total(report: Dict[str, Any], status: str) -> int:
        return sum(int(r["link"]["statuses"][status]) for r in report["routes"])

    assert total(default, "OKSOMELOST") > 0
    assert total(strict, "OKSOMELOST") == 0
    assert total(strict, "WRONGSEQUENCE") > total(default, "WRONGSEQUENCE")
    for report in (default, strict):
        assert report["summary"]["equal_routes"] == report["summary"]["routes"]


def test_link_bad_link_setting_is_a_config_error(demo: Demo) -> None:
    with pytest.raises(sds.ConfigError, match="1..=32"):
        sds.link(demo.results, telemetry=demo.telemetry, to="exec:true", settings={"link.window": 40})


def without_latency(report: Dict[str, Any]) -> Dict[str, Any]:
    """The report but each route's `latency_ms` (wall-clock times of the exchange)."""
    out = json.loads(json.dumps(report))
    for r in out["routes"]:
        r["link"].pop("latency_ms", None)
    return out


def test_i48_1_link_takes_the_options_of_sds_link(sds_bin: Path, demo: Demo, tmp_path: Path) -> None:
    """`sds.link` builds the request `sds link` builds: `routes` (the lateral reference: more
    events on a route), `profile`, `duplicates`; the report is the command's (`settings`:
    `test_link_settings_reach_the_doer`)."""
    checker = f"exec:{sds_bin} checker"
    twice = [demo.results, demo.results]
    # Results given twice are refused as `sds score` refuses them, unless `duplicates` says.
    with pytest.raises(sds.RefusedError, match="duplicates"):
        sds.link(twice, telemetry=demo.telemetry, to=checker)
    got = sds.link(twice, telemetry=demo.telemetry, to=checker, routes=demo.routes,
                   profile="b2d-legacy", duplicates="first")
    out = tmp_path / "link.json"
    code, _, err = run_cli(
        sds_bin,
        ["link", "--results", str(demo.results), "--results", str(demo.results), "--telemetry",
         str(demo.telemetry), "--to", checker, "--routes", str(demo.routes), "--profile",
         "b2d-legacy", "--duplicates", "first", "-o", str(out)],
    )
    assert code == 0, err
    assert without_latency(got) == without_latency(json.loads(out.read_text()))
    assert got["summary"]["equal_routes"] == got["summary"]["routes"] == len(demo.records())
    # The route XML reached the request: the lateral reference adds events on some route.
    plain = sds.link(demo.results, telemetry=demo.telemetry, to=checker)
    events = lambda r: [x["link"]["events"] for x in r["routes"]]  # noqa: E731
    assert events(got) != events(plain)
    assert all(a >= b for a, b in zip(events(got), events(plain)))
    with pytest.raises(sds.ConfigError, match='profile="fast": expected physical'):
        sds.link(demo.results, to=checker, profile="fast")
