"""Long tables of a report (spec v1.4 §15), as ``sds score --tables`` writes them.

:func:`long_tables` turns the report dict of :func:`sds.score` into rows (``routes``: one per
route row, ``events``: one per entry of a route's ``events``), with the columns of
``routes.csv`` and ``events.csv`` (docs/TABLES-SCHEMA.md): nested objects joined with ``.``,
lists as JSON text, the report's key order. :func:`to_pandas` makes them DataFrames (pandas is
imported only then). The values are the report's own: nothing is recomputed. The frames
(``frames.csv``) need the telemetry, not the report: write them with ``sds score --tables DIR``
and read ``DIR/frames.csv`` with ``pandas.read_csv``.
"""

from __future__ import annotations

import importlib
import json
from typing import Any, Dict, List, Mapping, Sequence, Tuple

Row = Dict[str, Any]


def _flatten(prefix: str, value: Any, out: List[Tuple[str, Any]]) -> None:
    if isinstance(value, Mapping):
        for k, v in value.items():
            _flatten(f"{prefix}.{k}" if prefix else str(k), v, out)
    elif isinstance(value, list):
        out.append((prefix, json.dumps(value, separators=(",", ":"), ensure_ascii=False)))
    else:
        out.append((prefix, value))


def _table(keys: Sequence[str], rows: Sequence[Tuple[Sequence[Any], Mapping[str, Any]]]) -> Tuple[List[str], List[Row]]:
    """Columns (the JSON's key order; a key only some rows have after the key it follows there;
    a name that is always null where other rows hold an object under it left out) and rows."""
    names: List[str] = []
    filled: Dict[str, bool] = {}
    flat: List[List[Tuple[str, Any]]] = []
    for _, obj in rows:
        leaves: List[Tuple[str, Any]] = []
        _flatten("", obj, leaves)
        flat.append(leaves)
        at = 0
        for k, v in leaves:
            if k in names:
                at = names.index(k) + 1
            else:
                names.insert(at, k)
                at += 1
            filled[k] = filled.get(k, False) or v is not None
    columns = [
        n for n in names if filled[n] or not any(m.startswith(n + ".") for m in names)
    ]
    out: List[Row] = []
    for (key, _), leaves in zip(rows, flat):
        row: Row = dict(zip(keys, key))
        values = dict(leaves)
        row.update((c, values.get(c)) for c in columns)
        out.append(row)
    return [*keys, *columns], out


def long_tables(report: Mapping[str, Any]) -> Dict[str, Tuple[List[str], List[Row]]]:
    """The ``routes`` and ``events`` tables of a report (the dict of :func:`sds.score`), each as
    (columns, rows); a row is a dict from column to value (``None`` for JSON null or a field the
    row does not have).

    >>> report = {"routes": [{"route_id": "R1", "comfort": {"score": 1.0}, "events": []}]}
    >>> long_tables(report)["routes"][0]
    ['route_index', 'route_id', 'comfort.score', 'events']
    """
    routes: List[Tuple[Sequence[Any], Mapping[str, Any]]] = []
    events: List[Tuple[Sequence[Any], Mapping[str, Any]]] = []
    for i, r in enumerate(report.get("routes", [])):
        routes.append(([i], r))
        for j, e in enumerate(r.get("events", [])):
            events.append(([i, r.get("route_id"), j], e))
    return {
        "routes": _table(["route_index"], routes),
        "events": _table(["route_index", "route_id", "event_index"], events),
    }


def to_pandas(report: Mapping[str, Any]) -> Dict[str, Any]:
    """The report's long tables as pandas DataFrames: ``{"routes": ..., "events": ...}``, with
    the columns of ``sds score --tables`` (docs/TABLES-SCHEMA.md). Imports pandas (install it
    yourself; the package does not depend on it).

    >>> import sds  # doctest: +SKIP
    >>> tables = sds.to_pandas(sds.score("results.json", telemetry="telemetry"))  # doctest: +SKIP
    >>> tables["routes"].groupby("town")["ds_safe"].mean()  # doctest: +SKIP
    """
    pandas = importlib.import_module("pandas")

    return {
        name: pandas.DataFrame(rows, columns=columns)
        for name, (columns, rows) in long_tables(report).items()
    }
