"""The live CARLA example's whole code path, against a stand-in world replaying the demo run:
its events and alarms equal `sds score`'s."""

from __future__ import annotations

import sys
import types
from pathlib import Path
from typing import Any, Callable, Dict, List, Optional, Tuple

import pytest

import sds
from conftest import Demo, monitor_comfort, monitor_lateral, same

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "examples"))
import live_carla  # noqa: E402


class V:
    def __init__(self, v: List[float]) -> None:
        self.x, self.y, self.z = v


class Rotation:
    def __init__(self, v: List[float]) -> None:
        self.pitch, self.roll, self.yaw = v


class Transform:
    """`carla.Transform` stand-in (also what the wrapper spawns the sensor with)."""

    def __init__(self, entry: Optional[Dict[str, Any]] = None) -> None:
        self.entry = entry

    @property
    def location(self) -> V:
        assert self.entry is not None
        return V(self.entry["location"])

    @property
    def rotation(self) -> Rotation:
        assert self.entry is not None
        return Rotation(self.entry["rotation"])

    def get_forward_vector(self) -> V:
        assert self.entry is not None
        return V(self.entry["forward_vector"])

    def get_right_vector(self) -> V:
        assert self.entry is not None
        return V(self.entry["right_vector"])


FAKE_CARLA = types.SimpleNamespace(Transform=Transform)


class Ego:
    """A `carla.Vehicle` stand-in playing back metric_info entries."""

    def __init__(self) -> None:
        self.entry: Dict[str, Any] = {}

    def get_transform(self) -> Transform:
        return Transform(self.entry)

    def get_acceleration(self) -> V:
        return V(self.entry["acceleration"])

    def get_angular_velocity(self) -> V:
        return V(self.entry["angular_velocity"])


class Sensor:
    def __init__(self) -> None:
        self.callback: Optional[Callable[[Any], None]] = None
        self.destroyed = False

    def listen(self, cb: Callable[[Any], None]) -> None:
        self.callback = cb

    def stop(self) -> None:
        pass

    def destroy(self) -> None:
        self.destroyed = True


class World:
    def __init__(self) -> None:
        self.frame = 0
        self.sensors: List[Tuple[str, Any, Sensor]] = []

    def get_blueprint_library(self) -> Any:
        return types.SimpleNamespace(find=lambda name: name)

    def spawn_actor(self, blueprint: str, transform: Any, attach_to: Any) -> Sensor:
        s = Sensor()
        self.sensors.append((blueprint, attach_to, s))
        return s

    def get_snapshot(self) -> Any:
        return types.SimpleNamespace(frame=self.frame)


class Agent:
    def __init__(self, ego: Ego, with_metric_info: bool) -> None:
        self.ego = ego
        self.steps = 0
        if with_metric_info:
            self.get_metric_info = lambda: dict(ego.entry)

    def run_step(self, input_data: Any, timestamp: float) -> str:
        self.steps += 1
        return "control"


def collision(frame: int, actor: int, type_id: str) -> Any:
    return types.SimpleNamespace(frame=frame, other_actor=types.SimpleNamespace(id=actor, type_id=type_id))


@pytest.mark.parametrize("with_metric_info", [True, False])
def test_stand_in_world_replays_the_demo(demo: Demo, demo_report: Dict[str, Any], with_metric_info: bool) -> None:
    records = {r["route_id"]: r for r in demo.records()}
    nodecel_alarms = 0
    for route in demo_report["routes"]:
        record = records[route["route_id"]]
        ticks = demo.metric_info(record["save_name"])
        world, ego = World(), Ego()
        agent = Agent(ego, with_metric_info)
        seen: List[str] = []
        wrapper = live_carla.SdsMonitoredAgent(
            agent, world, ego, route=demo.waypoints(route["route_id"]), dt=route["dt"], carla_module=FAKE_CARLA,
            on_alarm=lambda message, event: seen.append(message),
        )
        blueprint, attached, sensor = world.sensors[0]
        assert (blueprint, attached) == ("sensor.other.collision", ego) and sensor.callback
        hits = {e["frame"]: e for e in route["collision_events"] if e["frame"] is not None}
        for i, (step, entry) in enumerate(ticks):
            world.frame = step
            ego.entry = entry
            if i in hits:  # reported by the sensor during the tick, from its thread
                sensor.callback(collision(step, 1000 + i, hits[i]["type_id"]))
                sensor.callback(collision(step, 1000 + i, hits[i]["type_id"]))  # same contact
            assert wrapper.run_step(None, step * 0.05) == "control"
        done = wrapper.finish(
            score_route=record["scores"]["score_route"], score_penalty=record["scores"]["score_penalty"],
            workzone=route["collisions"]["workzone"],
        )
        assert sensor.destroyed and agent.steps == len(ticks)
        # The live summary is the CLI's per-route result.
        assert done["frames"] == route["frames"]
        assert same(done["comfort"], monitor_comfort(route["comfort"])) and same(done["lateral"], monitor_lateral(route["lateral"]))
        assert done["collisions"]["nodecel"] == route["collisions"]["nodecel"]
        assert same(done["ds_safe"], route["ds_safe"])
        # Each collision verdict as it happened is the report's.
        verdicts = [e for e in wrapper.events if e["kind"] == "collision"]
        assert [(v["frame"], v["decelerated"], v["exempt"]) for v in verdicts] == [
            (e["frame"], e["decelerated"], e["exempt"]) for e in route["collision_events"] if e["frame"] is not None
        ]
        # One alarm per penalised collision, uncomfortable chunk and lateral excess.
        comfort = route["comfort"]
        expected = (route["collisions"]["nodecel"] + comfort["chunks"] - comfort["comfortable"]
                    + route["lateral"]["anomalous"] + route["lateral"]["critical"])
        assert seen == wrapper.alarms and len(seen) == expected
        nodecel_alarms += sum("without deceleration" in m for m in seen)
    assert nodecel_alarms == sum(r["collisions"]["nodecel"] for r in demo_report["routes"]) >= 1


def test_alarms_are_logged_by_default(caplog: pytest.LogCaptureFixture) -> None:
    world, ego = World(), Ego()
    wrapper = live_carla.SdsMonitoredAgent(Agent(ego, True), world, ego, carla_module=FAKE_CARLA)
    entry = {"acceleration": [0.0, 0.0, 0.0], "angular_velocity": [0.0, 0.0, 0.0], "forward_vector": [1.0, 0.0, 0.0],
             "right_vector": [0.0, 1.0, 0.0], "location": [0.0, 0.0, 0.0], "rotation": [0.0, 0.0, 0.0]}
    for i in range(30):
        world.frame = 100 + i
        ego.entry = {**entry, "location": [0.4 * i, 0.0, 0.0]}  # 8 m/s
        if i == 25:
            world.sensors[0][2].callback and world.sensors[0][2].callback(collision(world.frame, 7, "vehicle.audi.tt"))
        with caplog.at_level("WARNING", logger="sds.live"):
            wrapper.run_step(None, 0.0)
    assert any("collision (1 vehicle) at 8.0 m/s without deceleration" in r.message for r in caplog.records)
