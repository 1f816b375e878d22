"""The SafeDriving Score (SDS) of Bench2Drive / CARLA runs, from Python.

Built from the same Rust code as the ``sds`` command (installed with this package):

- :func:`score` scores a run and returns the report of ``sds score --format json`` as a dict,
  the same numbers to the bit;
- :func:`compare` compares runs against a baseline (paired deltas, bootstrap intervals,
  verdicts, flips) and returns the report of ``sds compare --format json``;
- :class:`Monitor` is the streaming monitor of one route, fed the dict Bench2Drive's
  ``get_metric_info()`` returns each tick; it returns that tick's events as they happen.

Errors raise :class:`SdsError` subclasses whose messages are those of the ``sds`` command:
:class:`InputError` (a bad input file or frame), :class:`ConfigError` (a bad option or setting;
its subclass :class:`NeedsLabelsError`: a grouping without its label map),
:class:`IoError` (a file cannot be read), :class:`FeatureUnavailableError` (an option this build
does not have yet).
"""

from __future__ import annotations

import json
import os
from typing import Any, Dict, List, Mapping, Optional, Sequence, Union

from . import _sds
from ._sds import (
    ConfigError,
    FeatureUnavailableError,
    InputError,
    IoError,
    NeedsLabelsError,
    SdsError,
    __version__,
)
from ._compare import compare
from .monitor import Event, Monitor, Summary

__all__ = [
    "ConfigError",
    "Event",
    "FeatureUnavailableError",
    "InputError",
    "IoError",
    "Monitor",
    "NeedsLabelsError",
    "PathLike",
    "SdsError",
    "Summary",
    "__version__",
    "compare",
    "score",
]

PathLike = Union[str, "os.PathLike[str]"]
"""A path: a string or an ``os.PathLike`` (``pathlib.Path``)."""

_GROUPS = ("scenario", "family", "town", "weather", "route")
# The option that gives each grouping's label map.
_LABELS = {"family": "--families", "weather": "--weathers", "route": "--labels"}


def _paths(results: Union[PathLike, Sequence[PathLike]]) -> List[str]:
    if isinstance(results, (str, os.PathLike)):
        return [os.fspath(results)]
    return [os.fspath(r) for r in results]


def _feature(option: str, parameter: str, issue: int) -> None:
    """Raises :class:`FeatureUnavailableError` unless ``sds score`` has ``--option``."""
    if option not in _sds.score_options():
        raise FeatureUnavailableError(
            f"sds.score({parameter}=...): this build of sds has no `sds score --{option}` yet "
            f"(issue #{issue}); leave {parameter} at its default"
        )


def score(
    results: Union[PathLike, Sequence[PathLike]],
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
    progress: bool = False,
) -> Dict[str, Any]:
    """Scores a run; returns the report of ``sds score --format json`` as a dict.

    Every route is replayed through the streaming monitor (on ``jobs`` threads, default all
    cores, with the GIL released) and checked against the batch reference.

    Args:
        results: Evaluator results: a raw file, a merged file, or a folder of per-route files;
            or a list of them (``--results``, repeated).
        telemetry: The folder holding ``<save_name>/metric_info.json`` (``--telemetry``).
        routes: Bench2Drive's route XML, the lateral reference (``--routes``).
        maps: A folder of CARLA OpenDRIVE maps (``--maps``).
        profile: ``"physical"`` or ``"b2d-legacy"`` (``--profile``).
        duplicates: Routes recorded more than once: ``"error"`` (score nothing, name them),
            keep the ``"first"`` or ``"last"`` copy, or score ``"all"`` (``--duplicates``).
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
        progress: Draw a progress bar on standard error (when it is a terminal).

    Returns:
        The report (``schema``, ``profile``, ``config``, ``routes``, ``summary``, ``warnings``).
        Routes with problems are in it with their ``state``; the CLI would exit with 3.

    Raises:
        InputError: A results file, the route XML or a labels file is invalid; route ids are
            duplicated under ``duplicates="error"``; the inputs hold no record.
        IoError: A file or folder cannot be read (a ``telemetry`` folder that does not exist).
        ConfigError: An option or setting is invalid (``expected_routes`` below the routes found,
            ``group_by="family"`` or ``"route"`` without ``labels``).
        FeatureUnavailableError: ``maps`` or ``duplicates`` given where this build lacks them.

    Example:
        >>> report = sds.score("results/", telemetry="eval/", routes="bench2drive220.xml")
        >>> report["summary"]["sds"]  # doctest: +SKIP
    """
    args: List[str] = []
    for r in _paths(results):
        args += ["--results", r]
    if telemetry is not None:
        args += ["--telemetry", os.fspath(telemetry)]
    if routes is not None:
        args += ["--routes", os.fspath(routes)]
    if maps is not None:
        _feature("maps", "maps", 13)
        args += ["--maps", os.fspath(maps)]
    if duplicates != "error":
        _feature("duplicates", "duplicates", 11)
        args += ["--duplicates", duplicates]
    args += ["--profile", profile]
    if expected_routes is not None:
        args += ["--expected-routes", str(int(expected_routes))]
    if allow_missing_telemetry:
        args.append("--allow-missing-telemetry")
    for pair in _sds.settings_args(settings):
        args += ["--set", pair]
    if group_by is not None:
        if group_by not in _GROUPS:
            raise ConfigError(
                f"group_by={group_by!r}: expected one of {', '.join(_GROUPS)}"
            )
        args += ["--group-by", group_by]
    if labels is not None:
        if group_by not in _LABELS:
            raise ConfigError(
                "labels: give group_by='family' (scenario families), 'weather' (weather names) "
                "or 'route' (labels of route ids)"
            )
        args += [_LABELS[group_by], os.fspath(labels)]
    if jobs is not None:
        args += ["--jobs", str(int(jobs))]
    report: Dict[str, Any] = json.loads(_sds.score_json(args, progress=progress))
    return report
