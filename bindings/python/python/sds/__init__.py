"""The SafeDriving Score (SDS) of Bench2Drive / CARLA runs, from Python.

Built from the same Rust code as the ``sds`` command (installed with this package):

- :func:`score` scores a run and returns the report of ``sds score --format json`` as a dict,
  the same numbers to the bit;
- :func:`frames` returns the monitor's input frames of one route or vehicle log (``sds
  frames``);
- :func:`compare` compares runs against a baseline (paired deltas, bootstrap intervals,
  verdicts, flips) and returns the report of ``sds compare --format json``;
- :func:`merge` merges the reports of ``sds score`` scored where the files are (one per shard)
  into the report of ``sds score`` over all of them (``sds merge``);
- :func:`watch` scores an evaluation while it runs: an iterator of partial reports (the
  reports of ``sds watch``), for notebooks and dashboards;
- :func:`to_pandas` turns a report (or a folder of ``sds score --tables``) into DataFrames
  (``routes``, ``events``, ``frames``: the long tables, typed; :func:`long_tables` without
  pandas), :func:`to_parquet` writes them as Parquet, :func:`duckdb_read_csv` types DuckDB's
  read of the CSV files;
- :func:`log` logs a report to Weights & Biases, TensorBoard or MLflow, and a
  :class:`Tracker`'s ``on_round`` logs each round of :func:`watch`;
- :class:`Monitor` is the streaming monitor of one route, fed the dict Bench2Drive's
  ``get_metric_info()`` returns each tick; it returns that tick's events as they happen.

The report's warnings are Python warnings of the class :class:`SdsWarning` (a ``UserWarning``):
``warnings.simplefilter("error", sds.SdsWarning)`` makes them fatal, ``"ignore"`` silences them.

Errors raise :class:`SdsError` subclasses whose messages are those of the ``sds`` command:
:class:`InputError` (a bad input file or frame), :class:`ConfigError` (a bad option or setting;
its subclass :class:`NeedsLabelsError`: a grouping without its label map),
:class:`IoError` (a file cannot be read), :class:`RefusedError` (the inputs do not fit the
options: both an :class:`InputError` and a :class:`ConfigError`), :class:`FeatureUnavailableError`
(an option this build does not have yet).
"""

from __future__ import annotations

from ._options import PathLike

# The entry points are the extension's functions themselves (typed in Rust, documented there:
# ``help(sds.score)`` shows the signature and the docs; ``_sds.pyi`` carries the types).
from ._sds import (
    ConfigError,
    FeatureUnavailableError,
    InputError,
    IoError,
    NeedsLabelsError,
    RefusedError,
    SdsError,
    SdsWarning,
    Watch,
    __version__,
    compare,
    frames,
    link,
    merge,
    score,
    watch,
)
from ._tables import duckdb_read_csv, long_tables, read_tables, to_pandas, to_parquet
from ._trackers import Tracker, log
from .monitor import Event, Monitor, Summary

__all__ = [
    "link",
    "ConfigError",
    "Event",
    "FeatureUnavailableError",
    "InputError",
    "IoError",
    "Monitor",
    "NeedsLabelsError",
    "PathLike",
    "RefusedError",
    "SdsError",
    "SdsWarning",
    "Summary",
    "Tracker",
    "Watch",
    "__version__",
    "compare",
    "duckdb_read_csv",
    "frames",
    "merge",
    "log",
    "long_tables",
    "read_tables",
    "score",
    "to_pandas",
    "to_parquet",
    "watch",
]
