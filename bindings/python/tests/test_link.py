"""`sds.link`: the demo run played to the host checker (`sds checker`) through the library
(issue 49); the same report as `sds link`."""

from __future__ import annotations

from pathlib import Path

import pytest

import sds
from conftest import Demo


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
