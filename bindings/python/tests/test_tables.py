"""`sds.long_tables` and `sds.to_pandas` (issue 37, spec v1.4 §15): the columns and values of
`sds score --tables`' routes.csv and events.csv, from the report dict."""

from __future__ import annotations

import csv
from pathlib import Path
from typing import Any, List

import pytest

import sds
from conftest import Demo, run_cli


def _cell_holds(cell: str, v: Any) -> bool:
    """A CSV cell of the Rust tables holds the Python value (floats by value: Python's repr
    writes `e-09` where the JSON writes `e-9`)."""
    if v is None:
        return cell == ""
    if isinstance(v, bool):
        return cell == ("true" if v else "false")
    if isinstance(v, float):
        return float(cell) == v
    if isinstance(v, str) and cell.startswith("'"):
        return cell[1:] == v  # the CSV's formula guard
    return cell == str(v)


def test_long_tables_equal_the_cli_tables(demo: Demo, sds_bin: Path, tmp_path: Path) -> None:
    out = tmp_path / "tables"
    code, _, err = run_cli(
        sds_bin,
        ["score", "--results", str(demo.results), "--telemetry", str(demo.telemetry),
         "--routes", str(demo.routes), "--format", "json", "-o", str(tmp_path / "r.json"),
         "--tables", str(out)],
    )
    assert code == 0, err
    report = sds.score(demo.results, telemetry=demo.telemetry, routes=demo.routes)
    tables = sds.long_tables(report)
    assert set(tables) == {"routes", "events"}
    for name, (columns, rows) in tables.items():
        with open(out / f"{name}.csv", newline="", encoding="utf-8") as f:
            reader = csv.reader(f)
            header = next(reader)
            cli_rows: List[List[str]] = list(reader)
        assert columns == header, name
        assert len(rows) == len(cli_rows) > 0, name
        for row, cli_row in zip(rows, cli_rows):
            for c, cell in zip(columns, cli_row):
                assert _cell_holds(cell, row[c]), (name, c, row[c], cell)
    assert len(tables["routes"][1]) == len(report["routes"])


def test_to_pandas_gives_typed_frames(demo: Demo) -> None:
    pandas = pytest.importorskip("pandas", reason="pandas is not installed")
    report = sds.score(demo.results, telemetry=demo.telemetry, routes=demo.routes)
    frames = sds.to_pandas(report)
    routes = frames["routes"]
    assert isinstance(routes, pandas.DataFrame)
    assert list(routes.columns) == sds.long_tables(report)["routes"][0]
    assert len(routes) == len(report["routes"])
    assert routes["ds_safe"].dtype.kind == "f"
    assert routes["frames"].dtype.kind in "iu"
    assert list(routes["route_id"]) == [r["route_id"] for r in report["routes"]]
    assert len(frames["events"]) == sum(len(r["events"]) for r in report["routes"])
