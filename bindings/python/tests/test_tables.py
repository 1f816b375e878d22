"""`sds.long_tables`, `sds.to_pandas`, `sds.to_parquet` and the DuckDB query of USAGE.md
(issue 37, docs/TABLES-SCHEMA.md): the columns and values of `sds score --tables`' routes.csv,
events.csv and frames.csv, from the report dict (through the Rust builder) and from the folder,
typed as docs/TABLES-SCHEMA.md says."""

from __future__ import annotations

import csv
import json
import math
import re
from pathlib import Path
from typing import Any, Dict, List

import pytest

import sds
from conftest import REPO, Demo, run_cli


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


def _cli_tables(sds_bin: Path, demo: Demo, out: Path) -> Path:
    code, _, err = run_cli(
        sds_bin,
        ["score", "--results", str(demo.results), "--telemetry", str(demo.telemetry),
         "--routes", str(demo.routes), "--format", "json", "-o", str(out / "r.json"),
         "--tables", str(out / "tables")],
    )
    assert code == 0, err
    return out / "tables"


def _csv(path: Path) -> List[List[str]]:
    with open(path, newline="", encoding="utf-8") as f:
        return list(csv.reader(f))


def _same(a: Any, b: Any) -> bool:
    if isinstance(a, float) and isinstance(b, float) and math.isnan(a) and math.isnan(b):
        return True
    return bool(a == b) and type(a) is type(b)


def test_schema_types_are_the_schema_files(demo: Demo) -> None:
    """sds._schema.TYPES is docs/TABLES-SCHEMA.md's type column, table by table."""
    doc = REPO / "docs" / "TABLES-SCHEMA.md"
    if not doc.exists():
        pytest.skip(f"{doc} is absent (the tests run outside the repository)")
    from sds import _schema

    parsed: Dict[str, Dict[str, str]] = {}
    table = ""
    for line in doc.read_text(encoding="utf-8").splitlines():
        m = re.match(r"## (\w+)\.csv", line)
        if m:
            table = m.group(1)
            parsed[table] = {}
        m = re.match(r"\| `([^`]+)` \| (\w+) \|", line)
        if m and table:
            parsed[table][m.group(1)] = m.group(2)
    assert parsed == _schema.TYPES
    assert _schema.column_type("routes", "protocols.lb2.0.penalty") == "float"
    assert _schema.column_type("routes", "weather_id") == "string"


def test_folder_tables_are_typed_as_the_schema(demo: Demo, sds_bin: Path, tmp_path: Path) -> None:
    """read_tables/to_pandas on a --tables folder: every table, the CSV's rows, each column of
    the schema's type; routes and events equal the report's (through the Rust builder)."""
    pandas = pytest.importorskip("pandas", reason="pandas is not installed")
    folder = _cli_tables(sds_bin, demo, tmp_path)
    tables = sds.read_tables(folder)
    assert set(tables) == {"routes", "events", "frames"}
    for name, (columns, data) in tables.items():
        rows = _csv(folder / f"{name}.csv")
        assert columns == rows[0]
        assert all(len(v) == len(rows) - 1 for v in data.values()), name
    # weather_id is text though its cells are digits; frames' host.step an int.
    assert all(isinstance(v, str) for v in tables["routes"][1]["weather_id"])
    assert all(isinstance(v, int) for v in tables["frames"][1]["host.step"])
    report = sds.score(demo.results, telemetry=demo.telemetry, routes=demo.routes)
    from_report = sds.long_tables(report)
    for name in ("routes", "events"):
        columns, data = tables[name]
        rcols, rrows = from_report[name]
        assert columns == rcols
        for c in columns:
            for i, row in enumerate(rrows):
                v, w = data[c][i], row[c]
                if isinstance(w, str) and isinstance(v, str) and v.startswith("'"):
                    v = v[1:]  # the CSV's formula guard
                assert v == w, (name, c, i, v, w)
    frames = sds.to_pandas(folder)
    assert isinstance(frames["frames"], pandas.DataFrame)
    assert frames["frames"]["a_lon"].dtype.kind == "f"
    assert str(frames["frames"]["frame"].dtype) == "Int64"
    assert str(frames["routes"]["success"].dtype) == "boolean"
    assert len(frames["frames"]) == sum(r["frames"] for r in report["routes"] if r["telemetry"] == "ok")


def test_to_parquet_reads_back_equal_to_the_csv_and_the_json(demo: Demo, sds_bin: Path, tmp_path: Path) -> None:
    """to_parquet of a --tables folder and of the report: read back with pyarrow, the values of
    the CSV files (and of the JSON report for routes and events), the schema's types."""
    pa = pytest.importorskip("pyarrow", reason="pyarrow is not installed (scripts/setup.sh downloads it)")
    pq = pytest.importorskip("pyarrow.parquet", reason="pyarrow is not installed")
    folder = _cli_tables(sds_bin, demo, tmp_path)
    written = sds.to_parquet(folder, tmp_path / "pq")
    assert [p.name for p in written] == ["routes.parquet", "events.parquet", "frames.parquet"]
    csv_tables = sds.read_tables(folder)
    for name, (columns, data) in csv_tables.items():
        t = pq.read_table(tmp_path / "pq" / f"{name}.parquet")
        assert t.column_names == columns
        back = t.to_pydict()
        for c in columns:
            assert back[c] == data[c], (name, c)
    routes = pq.read_table(tmp_path / "pq" / "routes.parquet").schema
    assert routes.field("ds_safe").type == pa.float64()
    assert routes.field("frames").type == pa.int64()
    assert routes.field("success").type == pa.bool_()
    assert routes.field("weather_id").type == pa.string()
    report = sds.score(demo.results, telemetry=demo.telemetry, routes=demo.routes)
    sds.to_parquet(report, tmp_path / "pq-report")
    r = pq.read_table(tmp_path / "pq-report" / "routes.parquet").to_pydict()
    assert r["route_id"] == [x["route_id"] for x in report["routes"]]
    assert r["ds_safe"] == [x["ds_safe"] for x in report["routes"]]
    assert r["comfort.score"] == [x["comfort"]["score"] for x in report["routes"]]
    assert r["events"] == [json.dumps(x["events"], separators=(",", ":"), ensure_ascii=False) for x in report["routes"]]
    # The DataFrames of to_pandas write the same file.
    sds.to_parquet(sds.to_pandas(report), tmp_path / "pq-pandas")
    p = pq.read_table(tmp_path / "pq-pandas" / "routes.parquet").to_pydict()
    assert p["ds_safe"] == r["ds_safe"] and p["route_id"] == r["route_id"]


def _usage_query() -> str:
    usage = REPO / "docs" / "USAGE.md"
    if not usage.exists():
        pytest.skip(f"{usage} is absent (the tests run outside the repository)")
    text = usage.read_text(encoding="utf-8")
    m = re.search(r"<!-- duckdb-query -->\s*```sql\n(.*?)```", text, re.S)
    assert m, "docs/USAGE.md has no SQL block after <!-- duckdb-query -->"
    return m.group(1)


def test_duckdb_query_of_usage_runs_over_csv_and_parquet(demo: Demo, sds_bin: Path, tmp_path: Path) -> None:
    """The DuckDB query of docs/USAGE.md over the tables (CSV and Parquet): per route, the
    frames' peak lateral acceleration next to the route's DS_safe, equal to pandas'."""
    duckdb = pytest.importorskip("duckdb", reason="duckdb is not installed (scripts/setup.sh downloads it)")
    pytest.importorskip("pyarrow", reason="pyarrow is not installed")
    folder = _cli_tables(sds_bin, demo, tmp_path)
    sds.to_parquet(folder, tmp_path / "pq")
    query = _usage_query()
    results = []
    for where, ext in ((folder, "csv"), (tmp_path / "pq", "parquet")):
        q = query.replace("tables/", f"{where}/").replace(".csv", f".{ext}")
        con = duckdb.connect()
        results.append(con.execute(q).fetchall())
    assert results[0] == results[1] and len(results[0]) > 0
    frames = sds.to_pandas(folder)
    peak = frames["frames"].assign(a=frames["frames"]["a_lat"].abs()).groupby("route_id")["a"].max()
    for row in results[0]:
        route_id, max_a_lat = row[0], row[-1]
        assert abs(peak[route_id] - max_a_lat) < 1e-12, route_id


def test_long_tables_of_a_real_run_equal_the_cli_tables(b2d: Path, sds_bin: Path, tmp_path: Path) -> None:
    """A real Bench2Drive results file (no telemetry): the Rust builder's rows through the
    binding equal routes.csv and events.csv of sds score --tables."""
    results = b2d / "carla_garage_pdm_lite_b2d_traj_merged.json"
    code, _, err = run_cli(
        sds_bin,
        ["score", "--results", str(results), "--allow-missing-telemetry", "--format", "json",
         "-o", str(tmp_path / "r.json"), "--tables", str(tmp_path / "t")],
    )
    assert code in (0, 3), err
    report = json.loads((tmp_path / "r.json").read_text(encoding="utf-8"))
    tables = sds.long_tables(report)
    for name, (columns, rows) in tables.items():
        cli = _csv(tmp_path / "t" / f"{name}.csv")
        assert columns == cli[0], name
        assert len(rows) == len(cli) - 1, name
        for row, cells in zip(rows, cli[1:]):
            for c, cell in zip(columns, cells):
                assert _cell_holds(cell, row[c]), (name, c, row[c], cell)


def _snapshot(folder: Path) -> Dict[str, bytes]:
    """Every entry of a folder: name -> bytes (a link as ``-> target``)."""
    out: Dict[str, bytes] = {}
    for p in sorted(folder.iterdir()):
        out[p.name] = ("-> " + str(p.readlink())).encode() if p.is_symlink() else p.read_bytes()
    return out


def test_r4_01_to_parquet_refuses_a_planted_link_and_writes_nothing(demo: Demo, sds_bin: Path, tmp_path: Path) -> None:
    """Issue 47 finding 1: a link planted at DIR/routes.parquet in a shared folder was written
    through (its target, a mode-600 file, then started with PAR1). Now it is refused, naming the
    link; its target, the link and the folder are as they were."""
    pytest.importorskip("pyarrow", reason="pyarrow is not installed (scripts/setup.sh downloads it)")
    folder = _cli_tables(sds_bin, demo, tmp_path)
    victim = tmp_path / "victim"
    victim.write_bytes(b"secret")
    victim.chmod(0o600)
    shared = tmp_path / "shared"
    shared.mkdir()
    (shared / "routes.parquet").symlink_to(victim)
    before = _snapshot(shared)
    for source in (folder, sds.score(demo.results), sds.to_pandas(sds.score(demo.results))):
        with pytest.raises(sds.IoError, match=r"routes\.parquet: a symbolic link"):
            sds.to_parquet(source, shared)
        assert victim.read_bytes() == b"secret"
        assert _snapshot(shared) == before


def test_r4_01_to_parquet_is_all_or_nothing(demo: Demo, sds_bin: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Issue 47 finding 1: a disk that fills (ENOSPC) while the second file is written left the
    first one replaced. Now every file of the set is as before, and no temporary file is left."""
    import errno

    pq = pytest.importorskip("pyarrow.parquet", reason="pyarrow is not installed")
    folder = _cli_tables(sds_bin, demo, tmp_path)
    out = tmp_path / "pq"
    sds.to_parquet(sds.score(demo.results), out)  # a previous set (routes, events)
    (out / "frames.parquet").write_bytes(b"an older frames file")
    before = _snapshot(out)
    real = pq.write_table
    calls: List[Any] = []

    def full_disk(table: Any, where: Any, *args: Any, **kwargs: Any) -> None:
        calls.append(where)
        if len(calls) == 2:
            real(table, where, *args, **kwargs)  # part of the file, then the disk is full
            raise OSError(errno.ENOSPC, "No space left on device")
        real(table, where, *args, **kwargs)

    monkeypatch.setattr(pq, "write_table", full_disk)
    with pytest.raises(OSError, match="No space left"):
        sds.to_parquet(folder, out)
    assert len(calls) == 2
    assert _snapshot(out) == before
    monkeypatch.setattr(pq, "write_table", real)
    written = sds.to_parquet(folder, out)
    assert [p.name for p in written] == ["routes.parquet", "events.parquet", "frames.parquet"]
    assert sorted(p.name for p in out.iterdir()) == ["events.parquet", "frames.parquet", "routes.parquet"]
    assert pq.read_table(out / "frames.parquet").num_rows > 0


def test_i46_5a_duckdb_avg_over_a_run_without_telemetry_is_null(b2d: Path, sds_bin: Path, tmp_path: Path) -> None:
    """Issue 46 item 5a: in a run without telemetry (every public results file) seven numeric
    columns are empty on every route; DuckDB's sniffer reads them as text, and
    ``avg("comfort.score")`` was a Binder Error. The typed reads USAGE.md documents (its SQL
    after ``<!-- duckdb-typed -->``, ``sds.duckdb_read_csv``, the Parquet files) give NULL, and
    every other figure as the report has it."""
    duckdb = pytest.importorskip("duckdb", reason="duckdb is not installed (scripts/setup.sh downloads it)")
    results = b2d / "carla_garage_tfpp_b2d_traj_merged.json"
    code, _, err = run_cli(
        sds_bin,
        ["score", "--results", str(results), "--allow-missing-telemetry", "--format", "json",
         "-o", str(tmp_path / "r.json"), "--tables", str(tmp_path / "tables")],
    )
    assert code in (0, 3), err
    report = json.loads((tmp_path / "r.json").read_text(encoding="utf-8"))
    assert report["summary"]["mean_comfort"] is None
    con = duckdb.connect()
    # The query USAGE.md shows, as written (its path relative to the tables' parent).
    usage = (REPO / "docs" / "USAGE.md").read_text(encoding="utf-8")
    m = re.search(r"<!-- duckdb-typed -->\s*```sql\n(.*?)```", usage, re.S)
    assert m, "docs/USAGE.md has no SQL block after <!-- duckdb-typed -->"
    typed = m.group(1).replace("'tables/", f"'{tmp_path}/tables/")
    comfort, ds = con.execute(typed).fetchall()[0]
    assert comfort is None and ds == pytest.approx(report["summary"]["driving_score"], rel=1e-15)
    # The helper: every column of the schema typed, whatever the cells hold.
    routes = sds.duckdb_read_csv(tmp_path / "tables" / "routes.csv")
    kinds = {name: kind for name, kind, *_ in con.execute(f"DESCRIBE SELECT * FROM {routes}").fetchall()}
    from sds._schema import column_type

    want = {"int": "BIGINT", "float": "DOUBLE", "bool": "BOOLEAN", "string": "VARCHAR", "json": "VARCHAR"}
    for name, kind in kinds.items():
        assert kind == want[column_type("routes", name) or "string"], (name, kind)
    assert kinds["comfort.score"] == "DOUBLE" and kinds["dt"] == "DOUBLE" and kinds["batch_agrees"] == "BOOLEAN"
    row = con.execute(f'SELECT avg("comfort.score"), avg(score_composed), count(*) FROM {routes}').fetchall()[0]
    assert row[0] is None and row[2] == 220
    assert row[1] == pytest.approx(report["summary"]["driving_score"], rel=1e-15)
    # Every table of the folder, frames too (no rows, but the frame columns, typed).
    frames = sds.duckdb_read_csv(tmp_path / "tables" / "frames.csv")
    assert con.execute(f"SELECT max(abs(a_lat)), count(*) FROM {frames}").fetchall() == [(None, 0)]
    events = sds.duckdb_read_csv(tmp_path / "tables" / "events.csv")
    assert con.execute(f"SELECT count(*) FROM {events}").fetchall()[0][0] > 100
    # A quote in the path is written as SQL wants it.
    odd = tmp_path / "it's"
    odd.mkdir()
    (odd / "routes.csv").write_bytes((tmp_path / "tables" / "routes.csv").read_bytes())
    assert con.execute(f"SELECT count(*) FROM {sds.duckdb_read_csv(odd / 'routes.csv')}").fetchall() == [(220,)]
    # The Parquet files are typed too.
    pytest.importorskip("pyarrow", reason="pyarrow is not installed")
    sds.to_parquet(tmp_path / "tables", tmp_path / "pq")
    pq_avg = con.execute(f"SELECT avg(\"comfort.score\") FROM '{tmp_path}/pq/routes.parquet'").fetchall()
    assert pq_avg == [(None,)]
