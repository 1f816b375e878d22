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

import json
import os
from typing import Any, Callable, Dict, List, Literal, Mapping, Optional, Sequence, Union

from . import _sds
from ._sds import (
    ConfigError,
    FeatureUnavailableError,
    InputError,
    IoError,
    NeedsLabelsError,
    RefusedError,
    SdsError,
    SdsWarning,
    __version__,
)
from ._compare import compare
from ._options import PathLike, run_options
from ._options import strings as _strings
from ._options import paths as _paths
from ._sds import Watch
from ._tables import duckdb_read_csv, long_tables, read_tables, to_pandas, to_parquet
from ._trackers import Tracker, log
from ._warn import warn_each
from ._watch import watch
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



def score(
    results: Union[PathLike, Sequence[PathLike], None] = None,
    *,
    telemetry: Optional[PathLike] = None,
    routes: Optional[PathLike] = None,
    maps: Optional[PathLike] = None,
    profile: str = "physical",
    duplicates: str = "error",
    expected_routes: Optional[int] = None,
    allow_missing_telemetry: bool = False,
    settings: Optional[Mapping[str, Union[str, int, float, bool]]] = None,
    group_by: Optional[str] = None,
    labels: Optional[PathLike] = None,
    jobs: Optional[int] = None,
    progress: Union[bool, Callable[[int, int], Any]] = False,
    protocols: Optional[Sequence[str]] = None,
    route_subset: Optional[Literal["all", "found"]] = None,
    mcap: Optional[Sequence[PathLike]] = None,
    topics: Optional[Sequence[str]] = None,
) -> Dict[str, Any]:
    """Scores a run; returns the report of ``sds score --format json`` as a dict.

    The library is called directly (no command line in between) and the report converted to
    Python objects as ``json.loads`` would read the JSON report, keys in its order. Every route is replayed through the streaming monitor (on ``jobs`` threads, default all
    cores, with the GIL released) and checked against the batch reference.

    Args:
        results: Evaluator results: a raw file, a merged file, or a folder of per-route files;
            or a list of them (``--results``, repeated).
        telemetry: The folder holding ``<save_name>/metric_info.json`` (``--telemetry``).
        routes: Bench2Drive's route XML, the lateral reference (``--routes``).
        maps: A folder of CARLA OpenDRIVE maps (``--maps``).
        profile: ``"physical"``, ``"b2d-legacy"`` or ``"autoware"`` (``--profile``).
        duplicates: Routes recorded more than once: ``"error"`` (score nothing, name them),
            keep the ``"first"`` or ``"last"`` copy or the ``"newest"`` run, or score ``"all"``
            (``--duplicates``).
        expected_routes: The benchmark's size N, e.g. 220 (``--expected-routes``).
        allow_missing_telemetry: Score routes without telemetry without telemetry terms.
        settings: Overrides, e.g. ``{"slack": 0.9, "bounds.yaw_rate": 1.0}`` (``--set``; names
            are those of the report's ``config`` block).
        group_by: The breakdown (the report's ``groups``): ``scenario``, ``family``, ``town``,
            ``weather`` or ``route`` (``--group-by``).
        labels: The label map of the grouping, read and checked here: scenario type -> family
            for ``family`` (``--families``), weather id -> label for ``weather``
            (``--weathers``), route id -> label for ``route`` (``--labels``; keys ``"1711"``,
            ``"RouteScenario_1711"`` or ``"RouteScenario_1711_rep0"``, e.g. a difficulty or
            train/test split). ``family`` and ``route`` need one.
        jobs: Worker threads (``--jobs``).
        progress: ``True``: draw a progress bar on standard error (when it is a terminal). A
            callable: called with ``(done, total)`` after each route (from the worker threads,
            one call at a time), e.g. to drive a notebook's bar; an exception it raises stops
            the run between routes and is raised here.
        protocols: Also score every route under these scoring protocols: ids among ``"b2d"``,
            ``"lb2.0"``, ``"lb2.1"``, ``"lead-nds"``, ``"f2d"``, or ``["all"]`` (``--protocol``;
            the report's per-route and summary ``protocols``). The recorded events under other
            arithmetic, not a re-run.
        route_subset: Which routes of ``routes`` make the route set (``--route-subset``):
            ``"all"`` (every route of the XML; one without a record counts as 0) or ``"found"``
            (those with a record: a run of 20 routes scored over 20). None: the setting
            ``route_subset`` (default ``"all"``, or from ``settings``).
        mcap: Vehicle logs scored instead of ``results`` (``--mcap``): MCAP files of ROS 2
            messages or rosbag2 folders, each one route named by its file stem. The report
            holds no driving score, success rate, DS_safe or SDS (a log has no Leaderboard
            record; its warnings say so).
        topics: The logs' topics, ``"NAME=TOPIC"`` each (``--topic``): ``pose=/odom``,
            ``imu=/imu``, ``event=TOPIC``, ``path=TOPIC``; defaults ``pose=/odom``, ``imu=/imu``.

    Returns:
        The report (``schema``, ``profile``, ``config``, ``routes``, ``summary``, ``warnings``).
        Routes with problems are in it with their ``state``; the CLI would exit with 3.

    Warns:
        SdsWarning: Each of the report's ``warnings`` (what ``sds score`` prints as
            ``sds: warning: ...``), at the caller's line.

    Raises:
        InputError: A results file, the route XML or a labels file is invalid; the inputs hold no
            record.
        IoError: A file or folder cannot be read (a ``telemetry`` folder that does not exist).
        ConfigError: An option or setting is invalid (an unknown ``profile``, ``duplicates``,
            ``route_subset`` or ``group_by``); its subclass
            :class:`NeedsLabelsError`: ``group_by="family"`` or ``"route"`` without ``labels``.
        RefusedError: The inputs do not fit the options (an :class:`InputError` and a
            :class:`ConfigError`): route ids duplicated under ``duplicates="error"``,
            ``expected_routes`` below the routes counted, a label map that matches no route.

    Example:
        >>> report = sds.score("results/", telemetry="eval/", routes="bench2drive220.xml")
        >>> report["summary"]["sds"]  # doctest: +SKIP
    """
    options: Dict[str, Any] = {
        **run_options(
            profile=profile,
            duplicates=duplicates,
            expected_routes=expected_routes,
            allow_missing_telemetry=allow_missing_telemetry,
            settings=settings,
            jobs=jobs,
            protocols=protocols,
            route_subset=route_subset,
        ),
        "telemetry": telemetry,
        "routes": routes,
        "maps": maps,
        "group_by": group_by,
        "labels": labels,
        "progress": progress,
        "mcap": None if mcap is None else _paths(mcap),
        "topics": None if topics is None else _strings("topics", topics),
    }
    report: Dict[str, Any] = _sds.score([] if results is None else _paths(results), options)
    warn_each(report.get("warnings") or [])
    return report


def frames(
    results: Union[PathLike, Sequence[PathLike], None] = None,
    *,
    route_id: Optional[str] = None,
    mcap: Optional[PathLike] = None,
    topics: Optional[Sequence[str]] = None,
    telemetry: Optional[PathLike] = None,
    routes: Optional[PathLike] = None,
    maps: Optional[PathLike] = None,
    profile: str = "physical",
    duplicates: Optional[str] = None,
    settings: Optional[Mapping[str, Union[str, int, float, bool]]] = None,
) -> List[Dict[str, Any]]:
    """The monitor's input frames of one route, as ``sds frames`` prints them.

    One dict per frame, as ``json.loads`` reads each line of ``sds frames``: the core's frame
    (``a_lon``, ``a_lat``, ``a_mag``, ``yaw_rate``, ``speed``, ``lat_err``, ...) and ``host``,
    the values behind it (``step``, ``dt``, ``reference``, and where the lateral error is known
    ``lat_err``, ``slack``, ``lane_width``).

    Args:
        results: Results file(s) or folder(s), as for :func:`score`; none with ``mcap``.
        route_id: The route, ``RouteScenario_<id>_rep<k>`` (``--route-id``).
        mcap: A vehicle log instead of ``results`` (``--mcap``): an MCAP file or rosbag2 folder.
        topics: The log's topics, ``"NAME=TOPIC"`` each, as for :func:`score`.
        telemetry, routes, maps, profile, settings: As for :func:`score`.
        duplicates: Which copy of a duplicated route id to read, as for :func:`score`.

    Returns:
        The frames, in order.

    Warns:
        SdsWarning: Each warning met reading the frames (``"<route>: <text>"``).

    Raises:
        InputError: No such route, an invalid record or log. ConfigError: A bad option or
            setting, ``topics`` without ``mcap``, ``mcap`` with ``results``.

    Example:
        >>> f = sds.frames("results/", route_id="RouteScenario_1711_rep0", telemetry="eval/")  # doctest: +SKIP
        >>> f[0]["host"]["step"]  # doctest: +SKIP
    """
    text, warnings = _sds.frames(
        [] if results is None else _paths(results),
        route_id=route_id,
        mcap=None if mcap is None else os.fspath(mcap),
        topics=[] if topics is None else _strings("topics", topics),
        telemetry=None if telemetry is None else os.fspath(telemetry),
        routes=None if routes is None else os.fspath(routes),
        maps=None if maps is None else os.fspath(maps),
        profile=profile,
        duplicates=duplicates,
        settings=settings,
    )
    warn_each(warnings)
    return [json.loads(line) for line in text.splitlines() if line]


def link(
    results: Union[PathLike, Sequence[PathLike]],
    *,
    to: str,
    telemetry: Optional[PathLike] = None,
    pace: Literal["fast", "realtime"] = "fast",
    inject: Optional[str] = None,
    tap: Optional[PathLike] = None,
    settings: Optional[Mapping[str, Any]] = None,
) -> Dict[str, Any]:
    """Plays a run to a checker over a byte stream; returns the report of ``sds link``.

    Each route is played to the checker (``to``: ``"serial:DEVICE[@BAUD]"``,
    ``"tcp:HOST:PORT"`` or ``"exec:COMMAND"``, e.g. ``"exec:sds checker"``), and its events are
    compared with the replay of the frames the checker accepted, cut into the segments it
    started (docs/SCORE.md, "Live link").

    Args:
        results: Results file(s) or folder(s), as for :func:`score`.
        to: The checker.
        telemetry: The telemetry root.
        pace: ``"fast"`` (as fast as the checker reads) or ``"realtime"`` (one frame a period).
        inject: Faults, ``"drop=P,corrupt=P,duplicate=P,reorder=P,stall=SECONDS,seed=N"``.
        tap: A folder for ``sent.bin`` and ``received.bin``.
        settings: Settings by name (as ``--set``), the link's too (``link.max_delta``,
            ``link.timeout``, ``link.window``, ``link.max_errors``; they must match the
            checker's, e.g. ``to="exec:sds checker --set link.window=10"``).

    Returns:
        The report: ``routes`` (each with its ``link`` object) and ``summary``
        (``equal_routes`` of ``routes``).

    Raises:
        ConfigError: A bad ``to``, ``pace``, ``inject`` or setting.
        IoError: The checker cannot be reached or stops answering.

    Example:
        >>> r = sds.link("results.json", telemetry="telemetry", to="exec:sds checker")  # doctest: +SKIP
        >>> r["summary"]["equal_routes"] == r["summary"]["routes"]  # doctest: +SKIP
    """
    overrides = [(str(k), str(v)) for k, v in (settings or {}).items()]
    report: Dict[str, Any] = _sds.link(
        _paths(results),
        None if telemetry is None else str(telemetry),
        to,
        pace,
        inject or "",
        None if tap is None else str(tap),
        overrides,
    )
    return report


def merge(
    parts: Sequence[PathLike],
    *,
    duplicates: str = "error",
    host: bool = True,
) -> Dict[str, Any]:
    """Merges reports scored where the files are; returns the report of ``sds merge``.

    Each part is the JSON report of ``sds score`` (or ``sds.score``'s dict written with
    ``json.dump``) over one shard, all scored with the same settings and route XML. The merged
    report equals ``sds.score`` over all the shards' files in every field but ``inputs`` (the
    parts) and ``warnings`` (each part's, naming it); a merge of merges equals one merge.

    Args:
        parts: The parts' JSON files, in input order.
        duplicates: A route recorded in two parts: ``"error"`` (raise, naming both parts),
            keep the ``"first"`` or ``"last"`` part's record, the ``"newest"`` (latest
            ``save_name`` time stamp, which each row keeps), or score ``"all"``; the merged
            ``config.duplicates`` states the rule applied.
        host: Name this machine in ``inputs.provenance`` (``--set provenance.host=false``).

    Returns:
        The merged report.

    Warns:
        SdsWarning: Each of the merged report's ``warnings`` (each part's, naming it).

    Raises:
        RefusedError: A part is not an ``sds`` report, or was edited (a row out of range, its
            arithmetic broken, rows that are not its route set), parts were scored with
            different settings, route sets, route XML bytes, maps or label files, or a route is
            recorded in two parts under ``duplicates="error"`` (an
            :class:`InputError` and a :class:`ConfigError`).
        IoError: A part cannot be read.
        ConfigError: An unknown ``duplicates``.

    Example:
        >>> merged = sds.merge(["part0.json", "part1.json"])  # doctest: +SKIP
        >>> merged["summary"]["driving_score"]  # doctest: +SKIP
    """
    report: Dict[str, Any] = _sds.merge(_paths(parts), duplicates, host)
    warn_each(report.get("warnings") or [])
    return report
