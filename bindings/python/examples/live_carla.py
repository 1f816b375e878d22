"""Live SafeDriving Score monitoring of a Bench2Drive agent in CARLA.

Wrap the agent the leaderboard runs; every tick the wrapper feeds the monitor the ego's
``get_metric_info()`` dict and the collisions the ego's collision sensor reported for that
simulator frame, and logs alarms as they happen:

- a collision without deceleration in the second before it (the SDS ``nodecel`` penalty);
- an uncomfortable second (a comfort chunk failing a bound);
- a lane-corridor excess (an anomalous or critical lateral chunk; needs the route's waypoints).

Usage inside a leaderboard agent file (``world``/``ego`` from ``CarlaDataProvider``)::

    from live_carla import SdsMonitoredAgent
    monitored = SdsMonitoredAgent(agent, world, ego, route=route_waypoints)
    control = monitored.run_step(input_data, timestamp)   # instead of agent.run_step
    ...
    summary = monitored.finish()                          # at the route's end
"""

from __future__ import annotations

import importlib
import logging
import threading
from typing import Any, Callable, Dict, Iterable, List, Mapping, Optional, Tuple

import sds

log = logging.getLogger("sds.live")

Alarm = Callable[[str, sds.Event], None]
"""Called with a one-line message and the event, for each alarm."""


def metric_info(ego: Any) -> Dict[str, List[float]]:
    """The ego's state as Bench2Drive's ``get_metric_info()`` reports it each tick (CARLA units:
    m/s², deg/s, metres, degrees), read from a ``carla.Vehicle``."""
    t = ego.get_transform()

    def v(x: Any) -> List[float]:
        return [float(x.x), float(x.y), float(x.z)]

    return {
        "acceleration": v(ego.get_acceleration()),
        "angular_velocity": v(ego.get_angular_velocity()),
        "forward_vector": v(t.get_forward_vector()),
        "right_vector": v(t.get_right_vector()),
        "location": v(t.location),
        "rotation": [float(t.rotation.pitch), float(t.rotation.roll), float(t.rotation.yaw)],
    }


def describe(event: sds.Event) -> Optional[str]:
    """The alarm message of an event, or None when the event is no alarm."""
    kind = event["kind"]
    if kind == "collision" and event["nodecel"]:
        hit = ", ".join(f"{n} {k}" for k, n in event["collisions"].items() if n)
        return (f"frame {event['frame']}: collision ({hit}) at {event['speed']:.1f} m/s "
                "without deceleration before it")
    if kind == "comfort" and not event["comfortable"]:
        failed = ", ".join(k for k, bad in event["failed"].items() if bad)
        return f"comfort chunk {event['chunk']}: an uncomfortable second ({failed})"
    if kind == "lateral":
        return (f"lateral chunk {event['chunk']}: lane-corridor excess "
                f"{event['max_excess']:.2f} m ({event['band']})")
    return None


class SdsMonitoredAgent:
    """A Bench2Drive agent whose every ``run_step`` also feeds an :class:`sds.Monitor`.

    Args:
        agent: The agent (its ``run_step`` drives; its ``get_metric_info()`` is used when it has
            one, else the ego's state is read directly).
        world: The ``carla.World``.
        ego: The ego ``carla.Vehicle``; a ``sensor.other.collision`` is attached to it.
        route: The route's waypoints (``(x, y)`` or ``carla.Location``), for lateral alarms.
        profile, dt, settings: As :class:`sds.Monitor`.
        on_alarm: Called for each alarm (default: logged as a warning on ``sds.live``).
        repeat_seconds: Contacts with the same actor within this time count once (the sensor
            reports every physics step of a contact).
        carla_module: The ``carla`` module (default: imported).
    """

    def __init__(
        self,
        agent: Any,
        world: Any,
        ego: Any,
        *,
        route: Optional[Iterable[Any]] = None,
        profile: str = "physical",
        dt: float = 0.05,
        settings: Optional[Mapping[str, Any]] = None,
        on_alarm: Optional[Alarm] = None,
        repeat_seconds: float = 5.0,
        carla_module: Any = None,
    ) -> None:
        carla = carla_module if carla_module is not None else importlib.import_module("carla")
        self.agent = agent
        self.world = world
        self.ego = ego
        self.monitor = sds.Monitor(profile, dt, settings, route=route)
        self.events: List[sds.Event] = []
        self.alarms: List[str] = []
        self._on_alarm = on_alarm
        self._repeat_frames = max(1, round(repeat_seconds / dt))
        self._last_contact: Dict[int, int] = {}
        self._pending: List[Tuple[int, int, str]] = []
        self._lock = threading.Lock()
        blueprint = world.get_blueprint_library().find("sensor.other.collision")
        self.sensor = world.spawn_actor(blueprint, carla.Transform(), attach_to=ego)
        self.sensor.listen(self._on_collision)

    def _on_collision(self, event: Any) -> None:
        # Called from CARLA's sensor thread.
        with self._lock:
            self._pending.append((int(event.frame), int(event.other_actor.id), str(event.other_actor.type_id)))

    def _collisions_until(self, frame: int) -> List[str]:
        with self._lock:
            due = [p for p in self._pending if p[0] <= frame]
            self._pending = [p for p in self._pending if p[0] > frame]
        out = []
        for f, actor, type_id in due:
            last = self._last_contact.get(actor)
            self._last_contact[actor] = f
            if last is None or f - last > self._repeat_frames:
                out.append(type_id)
        return out

    def run_step(self, input_data: Any, timestamp: float) -> Any:
        """The agent's control for this tick; the monitor sees the tick first."""
        self.tick()
        return self.agent.run_step(input_data, timestamp)

    def tick(self) -> List[sds.Event]:
        """Pushes the current simulator frame to the monitor; returns its events."""
        frame = int(self.world.get_snapshot().frame)
        get_info = getattr(self.agent, "get_metric_info", None)
        info = get_info() if callable(get_info) else metric_info(self.ego)
        events = self.monitor.push(info, step=frame, collisions=self._collisions_until(frame))
        for e in events:
            self._event(e)
        return events

    def _event(self, event: sds.Event) -> None:
        self.events.append(event)
        message = describe(event)
        if message is None:
            return
        self.alarms.append(message)
        if self._on_alarm is not None:
            self._on_alarm(message, event)
        else:
            log.warning("%s", message)

    def finish(
        self,
        *,
        score_route: Optional[float] = None,
        score_penalty: Optional[float] = None,
        workzone: int = 0,
    ) -> sds.Summary:
        """Ends the route: removes the sensor, logs the last alarms, returns the summary."""
        self.sensor.stop()
        self.sensor.destroy()
        done = self.monitor.finish(score_route=score_route, score_penalty=score_penalty, workzone=workzone)
        for e in done["events"]:
            self._event(e)
        return done
