"""The streaming monitor of one route (:class:`Monitor`)."""

from __future__ import annotations

from array import array
from typing import Any, Dict, List, Mapping, Optional, Sequence

from . import _sds

Event = Dict[str, Any]
"""One event: ``kind`` (``"collision"``, ``"comfort"`` or ``"lateral"``) and its verdict.

- ``collision``: ``frame``, ``collisions`` (counts by ``pedestrian``, ``vehicle``, ``layout``,
  ``workzone``), ``speed`` (m/s), ``decelerated``, ``exempt``, ``nodecel`` (penalised: no
  deceleration before it, ego moving);
- ``comfort``: ``chunk``, ``frames``, ``failed`` (one bool per bound), ``comfortable``;
- ``lateral``: ``chunk``, ``max_excess`` (m), ``band`` (``"anomalous"`` or ``"critical"``).
"""

Summary = Dict[str, Any]
"""What :meth:`Monitor.finish` returns: ``frames``, ``comfort`` (``chunks``, ``comfortable``,
``score``, ``failed``), ``lateral`` (``chunks``, ``scored_chunks``, ``anomalous``, ``critical``),
``collisions`` (``aligned``, ``exempt``, ``nodecel``), ``events`` (those of the route's end),
``p_safe`` and ``ds_safe`` (None unless the evaluator's scores are given)."""

_FIELDS: List[str] = list(_sds.FIELDS)


def _f64_bytes(columns: Sequence[Any], n: int, width: int) -> bytes:
    """``columns`` (each ``n`` rows of at least ``width`` numbers, or ``n`` numbers when
    ``width`` is 0) side by side, as native f64 bytes."""
    np: Any
    try:
        import numpy as np
    except ImportError:  # pragma: no cover - numpy is optional
        np = None
    if np is not None:
        parts = []
        for c in columns:
            a = np.asarray(c, dtype=np.float64)
            if width:
                if a.ndim != 2 or a.shape[0] != n or a.shape[1] < width:
                    raise _sds.InputError(
                        f"push_arrays: expected {n} rows of {width} numbers, got shape {a.shape}"
                    )
                a = a[:, :width]
            elif a.shape != (n,):
                raise _sds.InputError(f"push_arrays: expected {n} numbers, got shape {a.shape}")
            parts.append(a.reshape(n, -1))
        return bytes(np.ascontiguousarray(np.hstack(parts)).tobytes())
    out = array("d")
    for i in range(n):
        for c in columns:
            if width:
                row = c[i]
                out.extend(float(row[k]) for k in range(width))
            else:
                out.append(float(c[i]))
    return out.tobytes()


class Monitor(_sds.Monitor):
    """The streaming SDS monitor of one route, one simulator tick at a time.

    Frames are built exactly as ``sds score`` builds them from ``metric_info.json`` (the
    acceleration projected on the forward and right vectors by the monitor's f32 kernels, the
    yaw rate in CARLA's deg/s, the speed from consecutive locations and ``dt``), then pushed
    through the same monitor as the firmware: the same events and summary, to the bit.

    Args:
        profile: ``"physical"``, ``"b2d-legacy"`` or ``"autoware"``.
        dt: The simulator step in seconds (Bench2Drive: 0.05).
        settings: Overrides by the report's ``config`` names, e.g. ``{"slack": 0.9}``.
        route: The route's reference waypoints, ``(x, y)`` or ``(x, y, z)`` tuples or
            ``carla.Location``-like objects (e.g. the route XML's ``<position>`` elements):
            each frame's lateral error is then measured against it as ``sds score --routes``
            does. Without it (and without ``lateral_reference="lane"``), pass ``lat_err`` to
            :meth:`push` (or the lateral terms see no frame).
        maps: The town's OpenDRIVE map: a ``.xodr`` file, or a folder of maps (as
            ``sds score --maps``) with ``town`` naming the map to use. With a map, junction
            gaps of ``route`` are filled with the map's lanes and the slack comes from the lane
            width, as ``sds score --maps`` does.
        town: The town (e.g. ``"Town04"``) whose map to pick from the ``maps`` folder.
        lateral_reference: ``"route"`` (the default: the route's waypoints) or ``"lane"`` (the
            nearest driving lane of the map; needs ``maps``), as the setting
            ``lateral_reference`` of ``sds score``. :attr:`reference` tells which is used.

    Raises:
        ConfigError: An unknown profile or setting, or an invalid value; ``maps`` a folder
            without ``town``; ``lateral_reference="lane"`` without ``maps``.
        InputError: A route waypoint is not two finite numbers; a map that does not parse.
        IoError: The map cannot be read, or the folder has no map of ``town``.

    Example:
        >>> m = sds.Monitor()
        >>> for entry in ticks:                      # get_metric_info() dicts
        ...     for event in m.push(entry):
        ...         print(event["kind"], event)
        >>> m.finish()["comfort"]["score"]
    """

    def push_arrays(
        self,
        acceleration: Any,
        angular_velocity: Any,
        forward_vector: Any,
        right_vector: Any,
        location: Any,
        *,
        steps: Optional[Sequence[int]] = None,
        collisions: Optional[Mapping[int, Sequence[str]]] = None,
        lat_err: Optional[Any] = None,
    ) -> List[Event]:
        """Pushes a whole route (or a stretch of it) given as arrays; returns its events.

        Args:
            acceleration, angular_velocity, forward_vector, right_vector, location: ``n`` rows
                of 3 numbers each (numpy arrays of shape ``(n, 3)``, or sequences of rows).
            steps: The ``n`` step numbers (default: following the last step, 1 apart).
            collisions: Row index → that frame's collisions (as :meth:`push` takes them).
            lat_err: ``n`` lateral errors in metres; NaN where unknown.

        Raises:
            InputError: A row is invalid (NaN, too large for f32), the shapes differ, or the
                steps do not increase. Frames before the bad one stay pushed.
        """
        n = len(location)
        data = _f64_bytes(
            [acceleration, angular_velocity, forward_vector, right_vector, location], n, 3
        )
        lat = None if lat_err is None else _f64_bytes([lat_err], n, 0)
        step_list = None if steps is None else [int(s) for s in steps]
        coll = None if collisions is None else {int(k): list(v) for k, v in collisions.items()}
        events: List[Event] = self._push_raw(n, data, step_list, lat, coll)
        return events


__all__ = ["Event", "Monitor", "Summary"]
