"""Bad inputs raise the documented exceptions, with the `sds` command's messages."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Dict, List

import pytest

import sds
from conftest import Demo, run_cli


def cli_error(sds_bin: Path, args: List[str]) -> str:
    code, _, err = run_cli(sds_bin, ["score", *args])
    assert code in (1, 2, 4), err  # no report: unreadable input, usage, empty run
    line = [l for l in err.splitlines() if l.startswith("sds: error: ")]
    assert line, err
    return line[0][len("sds: error: "):]


def test_hierarchy() -> None:
    for cls in (sds.InputError, sds.ConfigError, sds.IoError, sds.FeatureUnavailableError):
        assert issubclass(cls, sds.SdsError)
        assert cls.__bases__ == (sds.SdsError,), cls
    assert sds.NeedsLabelsError.__bases__ == (sds.ConfigError,)
    assert issubclass(sds.SdsError, Exception)
    for cls in (sds.SdsError, sds.InputError, sds.ConfigError, sds.NeedsLabelsError, sds.IoError):
        assert cls.__module__ == "sds", cls


def test_group_by_without_labels_is_needs_labels_error(sds_bin: Path, demo: Demo) -> None:
    with pytest.raises(sds.NeedsLabelsError) as e:
        sds.score(demo.results, group_by="family")
    assert type(e.value) is sds.NeedsLabelsError
    assert str(e.value) == "--group-by family needs its label map (--families FILE)"
    assert str(e.value) == cli_error(sds_bin, ["--results", str(demo.results), "--group-by", "family"])
    code, _, _ = run_cli(sds_bin, ["score", "--results", str(demo.results), "--group-by", "family"])
    assert code == 2  # a usage error, like every ConfigError


def test_unreadable_map_is_io_error(sds_bin: Path, demo: Demo, tmp_path: Path) -> None:
    maps = tmp_path / "maps"
    maps.mkdir()
    with open(maps / "DemoTown.xodr", "wb") as f:
        f.truncate(1536 << 20)  # sparse: over the reader's 1 GiB bound for a map, no disk used
    with pytest.raises(sds.IoError) as e:
        sds.score(demo.results, telemetry=demo.telemetry, routes=demo.routes, maps=maps)
    assert type(e.value) is sds.IoError
    args = ["--results", str(demo.results), "--telemetry", str(demo.telemetry), "--routes", str(demo.routes)]
    assert str(e.value) == cli_error(sds_bin, [*args, "--maps", str(maps)])
    assert str(e.value).startswith(f"{maps / 'DemoTown.xodr'}: cannot read the map: ")


def test_unreadable_results_is_io_error(sds_bin: Path, tmp_path: Path) -> None:
    missing = tmp_path / "nope.json"
    with pytest.raises(sds.IoError) as e:
        sds.score(missing)
    assert str(e.value) == cli_error(sds_bin, ["--results", str(missing)])
    assert str(e.value).count("No such file") == 1


def test_invalid_results_is_input_error(sds_bin: Path, tmp_path: Path) -> None:
    bad = tmp_path / "results"
    bad.mkdir()
    (bad / "r.json").write_text('{"_checkpoint": {"records": [')
    with pytest.raises(sds.InputError) as e:
        sds.score(bad / "r.json")
    assert str(e.value) == cli_error(sds_bin, ["--results", str(bad / "r.json")])
    assert "truncated JSON" in str(e.value)


def test_bad_route_xml_is_input_error(sds_bin: Path, demo: Demo, tmp_path: Path) -> None:
    xml = tmp_path / "routes.xml"
    xml.write_text("<routes><route id='1'>")
    with pytest.raises(sds.InputError) as e:
        sds.score(demo.results, routes=xml)
    assert str(e.value) == cli_error(sds_bin, ["--results", str(demo.results), "--routes", str(xml)])


def test_bad_setting_is_config_error(sds_bin: Path, demo: Demo) -> None:
    for settings, flag in [({"nope": 1}, "nope=1"), ({"slack": "abc"}, "slack=abc"), ({"chunk_len": 0}, "chunk_len=0")]:
        with pytest.raises(sds.ConfigError) as e:
            sds.score(demo.results, settings=settings)
        assert str(e.value) == cli_error(sds_bin, ["--results", str(demo.results), "--set", flag])
    with pytest.raises(sds.ConfigError, match="profile=\"fast\": expected one of physical, b2d-legacy"):
        sds.score(demo.results, profile="fast")
    with pytest.raises(sds.ConfigError, match="duplicates=\"most\": expected one of error, first, last, newest, all"):
        sds.score(demo.results, duplicates="most")


TICK: Dict[str, Any] = {
    "acceleration": [0.5, 0.1, 9.8], "angular_velocity": [0.0, 0.0, 2.0],
    "forward_vector": [1.0, 0.0, 0.0], "right_vector": [0.0, 1.0, 0.0],
    "location": [10.0, 5.0, 0.2], "rotation": [0.0, 0.0, 0.0],
}


@pytest.mark.parametrize(
    "change, message",
    [
        ({"location": None}, "step 7: field location: missing"),
        ({"acceleration": [1.0, 2.0]}, "step 7: field acceleration: fewer than 3 numbers"),
        ({"forward_vector": [1.0, "x", 0.0]}, "step 7: field forward_vector: non-numeric value"),
        ({"right_vector": 3.0}, "step 7: field right_vector: not an array of numbers"),
        ({"angular_velocity": [0.0, 0.0, math.nan]}, "step 7: field angular_velocity: NaN or infinite value"),
        ({"acceleration": [1e300, 0.0, 0.0]}, "step 7: field acceleration: value too large for f32"),
    ],
)
def test_bad_tick_is_input_error(change: Dict[str, Any], message: str) -> None:
    m = sds.Monitor()
    tick = {k: v for k, v in {**TICK, **change}.items() if v is not None}
    with pytest.raises(sds.InputError) as e:
        m.push(tick, step=7)
    assert str(e.value) == message
    assert m.frames == 0 and m.last_step is None  # nothing changed
    m.push(TICK, step=7)
    assert m.frames == 1


def test_monitor_misuse() -> None:
    m = sds.Monitor()
    m.push(TICK, step=3)
    with pytest.raises(sds.InputError, match="step 3: not after the previous step 3"):
        m.push(TICK, step=3)
    with pytest.raises(sds.InputError, match="lat_err"):
        m.push(TICK, step=4, lat_err=math.inf)
    with pytest.raises(sds.InputError, match='^step 4: collision "sensor.other.collision"'):
        m.push(TICK, collisions=["sensor.other.collision"])  # the step defaults to 3 + 1
    assert m.frames == 1
    m.finish()
    with pytest.raises(sds.SdsError):
        m.push(TICK, step=5)
    with pytest.raises(sds.SdsError):
        m.finish()
    with pytest.raises(sds.ConfigError):
        sds.Monitor(profile="fast")
    with pytest.raises(sds.ConfigError, match="unknown setting"):
        sds.Monitor(settings={"nope": 1})
    with pytest.raises(sds.InputError, match="route: waypoint 1"):
        sds.Monitor(route=[(0.0, 0.0), ("a", 1.0)])
    with pytest.raises(sds.InputError):
        sds.Monitor().push_arrays([[0, 0, 0]], [[0, 0, 0]], [[1, 0, 0]], [[0, 1, 0]], [[0, 0, 0], [1, 0, 0]])
