"""Long tables of a report (docs/TABLES-SCHEMA.md), as ``sds score --tables`` writes them.

The tables come from the Rust library's own builder (``_sds.long_tables``, the code that writes
``routes.csv`` and ``events.csv``): nothing here re-implements a table rule. :func:`long_tables`
gives them as rows; :func:`to_pandas` as DataFrames with typed columns (pandas imported only
then); :func:`to_parquet` writes them as Parquet (pyarrow imported only then);
:func:`duckdb_read_csv` gives DuckDB's typed read of a CSV file. The frames
(``frames.csv``) need the telemetry, not the report: write them with ``sds score --tables DIR``
and hand ``DIR`` to :func:`to_pandas` or :func:`to_parquet`, which read the CSV files and type
their columns.
"""

from __future__ import annotations

import csv
import functools
import importlib
import json
import os
import re
from pathlib import Path
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Tuple, Union

from . import _sds
from ._files import FileSet, refuse_unsafe
from ._schema import column_type

Row = Dict[str, Any]
Columns = Tuple[List[str], Dict[str, List[Any]]]
TABLES = ("routes", "events", "frames")
_INT = re.compile(r"-?[0-9]+\Z")


def _columns(report: Mapping[str, Any]) -> Dict[str, Columns]:
    text = json.dumps(report, ensure_ascii=False, allow_nan=False)
    tables: Dict[str, Columns] = _sds.long_tables(text)
    return tables


def long_tables(report: Mapping[str, Any]) -> Dict[str, Tuple[List[str], List[Row]]]:
    """The ``routes`` and ``events`` tables of a report (the dict of :func:`sds.score`), each as
    (columns, rows); a row is a dict from column to value (``None`` for JSON null or a field the
    row does not have; a list as its JSON text).

    >>> report = {"routes": [{"route_id": "R1", "comfort": {"score": 1.0}, "events": []}]}
    >>> long_tables(report)["routes"][0]
    ['route_index', 'route_id', 'comfort.score', 'events']
    """
    out: Dict[str, Tuple[List[str], List[Row]]] = {}
    for name, (columns, data) in _columns(report).items():
        n = len(data[columns[0]]) if columns else 0
        out[name] = (columns, [{c: data[c][i] for c in columns} for i in range(n)])
    return out


def _kind(table: str, column: str, values: Sequence[Any]) -> str:
    """The column's type: the schema's (docs/TABLES-SCHEMA.md), or for a column it does not
    name, the type of its values (``bool``, ``int``, ``float``, else ``string``)."""
    named = column_type(table, column)
    if named is not None:
        return named
    kinds = {type(v) for v in values if v is not None}
    if kinds == {bool}:
        return "bool"
    if kinds == {int}:
        return "int"
    if kinds and kinds <= {int, float}:
        return "float"
    return "string"


_PANDAS = {"bool": "boolean", "int": "Int64", "float": "float64"}


def _typed(kind: str, cells: Sequence[str]) -> List[Any]:
    """A CSV column's cells as the values of its type (an empty cell is null)."""
    if kind == "bool":
        return [None if c == "" else c == "true" for c in cells]
    if kind == "int":
        return [None if c == "" else int(c) for c in cells]
    if kind == "float":
        return [None if c == "" else float(c) for c in cells]
    return [None if c == "" else c for c in cells]


def _infer(cells: Sequence[str]) -> str:
    """The type of a column the schema does not name, from its cells."""
    filled = [c for c in cells if c != ""]
    if not filled:
        return "string"
    if all(c in ("true", "false") for c in filled):
        return "bool"
    if all(_INT.match(c) for c in filled):
        return "int"
    try:
        [float(c) for c in filled]
    except ValueError:
        return "string"
    return "float"


def read_tables(folder: Union[str, "os.PathLike[str]"]) -> Dict[str, Columns]:
    """The tables ``sds score --tables FOLDER`` (or ``sds compare --tables``) wrote, as
    ``{name: (columns, {column: values})}``, each column's cells read back as the values they
    write (:func:`to_pandas` and :func:`to_parquet` on a folder use this)."""
    out: Dict[str, Columns] = {}
    for name in TABLES:
        path = Path(folder) / f"{name}.csv"
        if not path.exists():
            continue
        with open(path, newline="", encoding="utf-8") as f:
            reader = csv.reader(f)
            columns = next(reader, [])
            rows = list(reader)
        data: Dict[str, List[Any]] = {}
        for i, c in enumerate(columns):
            cells = [r[i] if i < len(r) else "" for r in rows]
            data[c] = _typed(column_type(name, c) or _infer(cells), cells)
        out[name] = (columns, data)
    if not out:
        raise FileNotFoundError(f"{folder}: no routes.csv, events.csv or frames.csv (write them with sds score --tables {folder})")
    return out


Source = Union[Mapping[str, Any], str, "os.PathLike[str]"]


def _tables_of(source: Source) -> Dict[str, Columns]:
    if isinstance(source, (str, os.PathLike)):
        return read_tables(source)
    return _columns(source)


def to_pandas(source: Source) -> Dict[str, Any]:
    """The long tables as pandas DataFrames with typed columns (``Int64``, ``float64``,
    ``boolean``, text; docs/TABLES-SCHEMA.md): ``{"routes": ..., "events": ...}`` of a report
    (the dict of :func:`sds.score`), or ``{"routes", "events", "frames"}`` read from a folder
    ``sds score --tables`` wrote. Imports pandas (install it yourself; the package does not
    depend on it).

    >>> import sds  # doctest: +SKIP
    >>> tables = sds.to_pandas(sds.score("results.json", telemetry="telemetry"))  # doctest: +SKIP
    >>> tables["routes"].groupby("town")["ds_safe"].mean()  # doctest: +SKIP
    """
    pandas = importlib.import_module("pandas")
    return {
        name: pandas.DataFrame(
            {c: pandas.Series(data[c], dtype=_PANDAS.get(_kind(name, c, data[c]), object)) for c in columns},
            columns=columns,
        )
        for name, (columns, data) in _tables_of(source).items()
    }


_DUCKDB = {"int": "BIGINT", "float": "DOUBLE", "bool": "BOOLEAN", "string": "VARCHAR", "json": "VARCHAR"}


def _sql_string(text: str) -> str:
    return "'" + text.replace("'", "''") + "'"


def duckdb_read_csv(path: Union[str, "os.PathLike[str]"], table: Optional[str] = None) -> str:
    """DuckDB's ``read_csv(...)`` of a table ``sds score --tables`` wrote, every column typed as
    docs/TABLES-SCHEMA.md says (``int`` BIGINT, ``float`` DOUBLE, ``bool`` BOOLEAN, ``string``
    and ``json`` VARCHAR), to put after ``FROM``. DuckDB reads a CSV file's types from its
    cells, so a column empty on every row (``comfort.score``, ``dt``, ``distance_m``, ... in a
    run without telemetry) would be text, and ``avg("comfort.score")`` would not bind; typed,
    it is NULL. ``table`` (``routes``, ``events``, ``frames``) defaults to the file's name; the
    file's header is read to name its columns. DuckDB itself is not imported.

    >>> import duckdb, sds  # doctest: +SKIP
    >>> duckdb.sql(f'SELECT town, avg("comfort.score") FROM {sds.duckdb_read_csv("tables/routes.csv")} GROUP BY town')  # doctest: +SKIP
    """
    p = Path(path)
    name = table or p.stem
    if name not in TABLES:
        raise ValueError(f"{p}: table {name!r}: expected one of {', '.join(TABLES)} (pass table=...)")
    with open(p, newline="", encoding="utf-8") as f:
        columns = next(csv.reader(f), [])
    types = ", ".join(
        f"{_sql_string(c)}: '{_DUCKDB[k]}'" for c in columns if (k := column_type(name, c)) is not None
    )
    return f"read_csv({_sql_string(os.fspath(p))}, header = true, delim = ',', quote = '\"', types = {{{types}}})"


def _arrow_type(pa: Any, kind: str) -> Any:
    return {"bool": pa.bool_(), "int": pa.int64(), "float": pa.float64()}.get(kind, pa.string())


def _arrow_values(kind: str, values: Sequence[Any]) -> List[Any]:
    """The values as the type wants them (a whole number in a float column as a float)."""
    if kind == "float":
        return [None if v is None else float(v) for v in values]
    if kind in ("string", "json"):
        return [None if v is None else v if isinstance(v, str) else json.dumps(v) for v in values]
    return list(values)


def _arrow_table(pa: Any, name: str, columns: List[str], data: Dict[str, List[Any]]) -> Any:
    kinds = [_kind(name, c, data[c]) for c in columns]
    arrays = [pa.array(_arrow_values(k, data[c]), type=_arrow_type(pa, k)) for c, k in zip(columns, kinds)]
    return pa.Table.from_arrays(arrays, names=columns)


def to_parquet(source: Union[Source, Mapping[str, Any]], folder: Union[str, "os.PathLike[str]"]) -> List[Path]:
    """Writes the long tables as Parquet files ``routes.parquet``, ``events.parquet`` (and
    ``frames.parquet`` from a folder of ``sds score --tables``) into ``folder`` (created if
    needed); returns their paths. ``source``: a report (the dict of :func:`sds.score`), a folder
    ``sds score --tables`` wrote, or the dict of :func:`to_pandas`. Columns are typed as
    docs/TABLES-SCHEMA.md says (int64, double, bool, string; a list as its JSON text); a null is
    a Parquet null. Imports pyarrow (install it yourself; the package does not depend on it).

    The files are written as ``sds score --tables`` writes its own: each through a temporary
    file renamed over its name, a link at a name refused (:class:`sds.IoError`, naming it,
    before anything is written), and all or nothing: on an error (a full disk, Ctrl-C) the
    files this call replaced are put back and the ones it created removed.

    >>> import sds  # doctest: +SKIP
    >>> sds.to_parquet("tables/", "parquet/")  # doctest: +SKIP
    [PosixPath('parquet/routes.parquet'), PosixPath('parquet/events.parquet'), PosixPath('parquet/frames.parquet')]
    """
    pa = importlib.import_module("pyarrow")
    pq = importlib.import_module("pyarrow.parquet")
    out = Path(folder)
    tables: List[Tuple[str, Callable[[], Any]]] = []
    # The dict of to_pandas (DataFrames), not a report (whose "routes" is a list).
    if isinstance(source, Mapping) and "routes" in source and not isinstance(source["routes"], list):
        for name, df in source.items():
            tables.append((name, functools.partial(pa.Table.from_pandas, df, preserve_index=False)))
    elif isinstance(source, (str, os.PathLike)):
        # A folder: pyarrow reads the CSV itself, each column of the schema's type (880,000
        # frames: 1.4 s and 0.28 GB, against 10.4 s and 1.7 GB through Python lists).
        pa_csv = importlib.import_module("pyarrow.csv")
        paths = [(name, Path(source) / f"{name}.csv") for name in TABLES]
        paths = [(name, path) for name, path in paths if path.exists()]
        if not paths:
            read_tables(source)  # raises, naming the folder

        def from_csv(name: str, path: Path) -> Any:
            with open(path, newline="", encoding="utf-8") as f:
                columns = next(csv.reader(f), [])
            types = {c: _arrow_type(pa, k) for c in columns if (k := column_type(name, c)) is not None}
            return pa_csv.read_csv(
                path,
                convert_options=pa_csv.ConvertOptions(
                    column_types=types,
                    strings_can_be_null=True,
                    null_values=[""],
                    true_values=["true"],
                    false_values=["false"],
                ),
            )

        for name, path in paths:
            tables.append((name, functools.partial(from_csv, name, path)))
    else:
        for name, (columns, data) in _tables_of(source).items():

            tables.append((name, functools.partial(_arrow_table, pa, name, columns, data)))
    written = [out / f"{name}.parquet" for name, _ in tables]
    for path in written:
        refuse_unsafe(path)  # a planted link: refused before anything is written
    with FileSet(out) as files:
        for path, (_, table) in zip(written, tables):
            t = table()
            files.place(path, functools.partial(pq.write_table, t))
    return written
