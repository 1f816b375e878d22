"""`sds.Monitor` with the town's map (`maps=`) and either lateral reference
(`lateral_reference=`) builds the frames of `sds frames --maps ... --set lateral_reference=...`,
to the bit: the live monitor and the replay share the library's frame building."""

from __future__ import annotations

import json
import struct
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any, Dict, List, Optional, Tuple

import pytest

import sds
from conftest import Demo, run_cli


def f32(x: Optional[float]) -> Optional[bytes]:
    return None if x is None else struct.pack("<f", x)


def route_xml(demo: Demo, route_id: str) -> Tuple[str, List[Tuple[float, float, float]]]:
    """The town and the waypoints `(x, y, z)` of `RouteScenario_<id>_rep<k>` in the route XML."""
    xml_id = route_id.split("_")[1]
    for route in ET.parse(demo.routes).getroot().iter("route"):
        if route.get("id") == xml_id:
            points = [
                (float(p.get("x", "nan")), float(p.get("y", "nan")), float(p.get("z", "0")))
                for p in route.iter("position")
            ]
            return route.get("town", ""), points
    raise KeyError(route_id)


def cli_frames(sds_bin: Path, demo: Demo, route_id: str, reference: str) -> List[Dict[str, Any]]:
    code, out, err = run_cli(
        sds_bin,
        ["frames", "--results", str(demo.results), "--telemetry", str(demo.telemetry),
         "--routes", str(demo.routes), "--maps", str(demo.root / "maps"),
         "--set", f"lateral_reference={reference}", "--route-id", route_id],
    )
    assert code == 0, err
    return [json.loads(line) for line in out.splitlines()]


def kinds(counts: Dict[str, int]) -> List[str]:
    """A frame's collision counts as `push(collisions=...)` takes them."""
    return [k for k, n in counts.items() for _ in range(n)]


@pytest.mark.parametrize("reference", ["route", "lane"])
def test_live_with_map_equals_sds_frames(demo: Demo, sds_bin: Path, reference: str) -> None:
    maps = demo.root / "maps"
    assert (maps / "DemoTown.xodr").is_file()
    compared = known = outside = 0
    for n, record in enumerate(demo.records()):
        rid = record["route_id"]
        town, waypoints = route_xml(demo, rid)
        cli = cli_frames(sds_bin, demo, rid, reference)
        host = cli[0]["host"]
        # Half the routes find the map in the folder by town, the others get the file itself.
        where: Dict[str, Any] = {"maps": maps, "town": town} if n % 2 else {"maps": maps / f"{town}.xodr"}
        m = sds.Monitor(dt=host["dt"], route=waypoints, lateral_reference=reference, **where)
        assert m.reference == host["reference"], rid
        assert m.reference == ("map-lane" if reference == "lane" else "map-route"), rid
        ticks = demo.metric_info(record["save_name"])
        assert len(ticks) == len(cli), rid
        for (step, entry), frame in zip(ticks, cli):
            assert frame["host"]["step"] == step
            m.push(entry, step=step, collisions=kinds(frame.get("collisions", {})))
            ours = m.last_frame
            assert ours is not None
            for k in ("a_lon", "a_lat", "a_mag", "yaw_rate", "speed", "lat_err"):
                assert f32(ours[k]) == f32(frame.get(k)), f"{rid} step {step}: {k}: {ours[k]!r} != {frame.get(k)!r}"
            coll = {"pedestrian": 0, "vehicle": 0, "layout": 0, "workzone": 0, **frame.get("collisions", {})}
            assert ours["collisions"] == coll
            compared += 1
            known += ours["lat_err"] is not None
            outside += bool(ours["lat_err"])
    # Most frames have a lateral value; some of them leave their lane's slack.
    assert compared > 1000 and known > compared // 2 and outside > 10


def test_references_differ(demo: Demo, sds_bin: Path) -> None:
    """The two references give different lateral values on some route (the demo's lane change),
    else the test above could not tell one from the other."""
    differ = []
    for record in demo.records():
        rid = record["route_id"]
        route = [f.get("lat_err") for f in cli_frames(sds_bin, demo, rid, "route")]
        lane = [f.get("lat_err") for f in cli_frames(sds_bin, demo, rid, "lane")]
        if route != lane:
            differ.append(rid)
    assert differ


def test_map_errors(demo: Demo, tmp_path: Path) -> None:
    with pytest.raises(sds.ConfigError, match="name the town"):
        sds.Monitor(maps=demo.root / "maps")
    with pytest.raises(sds.IoError, match="no map for Town99"):
        sds.Monitor(maps=demo.root / "maps", town="Town99")
    with pytest.raises(sds.ConfigError, match="lateral_reference lane"):
        sds.Monitor(lateral_reference="lane")
    with pytest.raises(sds.ConfigError, match="lateral_reference"):
        sds.Monitor(lateral_reference="sideways")
    bad = tmp_path / "Bad.xodr"
    bad.write_text("<OpenDRIVE><road")
    with pytest.raises(sds.InputError):
        sds.Monitor(maps=bad)
    # Without a map, the route alone (junction gaps unknown).
    assert sds.Monitor(route=[(0.0, 0.0), (5.0, 0.0)]).reference == "xml"
    assert sds.Monitor().reference == "none"
