"""``sds.compare``: runs compared against a baseline (spec v1.3 section 11), from Python."""

from __future__ import annotations

import json
import os
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple, Union

from . import _sds

PathLike = Union[str, "os.PathLike[str]"]

Run = Union[PathLike, Tuple[PathLike, PathLike]]
"""A run: its results (file or folder), or ``(results, telemetry)``."""


def compare(
    runs: Mapping[str, Run],
    *,
    seeds: Optional[Mapping[str, Sequence[str]]] = None,
    baseline: Optional[str] = None,
    routes: Optional[PathLike] = None,
    maps: Optional[PathLike] = None,
    profile: str = "physical",
    expected_routes: Optional[int] = None,
    allow_missing_telemetry: bool = False,
    common_routes: bool = False,
    fail_if_worse: Optional[Sequence[str]] = None,
    bootstrap_samples: int = 10000,
    bootstrap_seed: int = 0,
    settings: Optional[Mapping[str, Union[str, int, float, bool]]] = None,
    jobs: Optional[int] = None,
) -> Dict[str, Any]:
    """Compares runs route by route; returns the ``sds-compare/1`` report as a dict.

    Each run is scored as :func:`sds.score` would; models (a run, or the seeds of one model)
    are compared with the baseline on the routes' paired differences, with a bootstrap interval
    and a verdict per metric (``ds``, ``success``, ``ds_safe``, ``comfort``).

    Args:
        runs: Run name -> results (file or folder; telemetry looked for beside it) or
            ``(results, telemetry)``. In order: the first model is the baseline.
        seeds: Model name -> the names of its runs (``--seeds``). Runs are grouped only here.
        baseline: The baseline model (``--baseline``; default the first).
        routes: The route XML every run is scored against (``--routes``).
        maps: A folder of OpenDRIVE maps (``--maps``).
        profile: ``"physical"`` or ``"b2d-legacy"``.
        expected_routes: The benchmark's size N (``--expected-routes``).
        allow_missing_telemetry: Score routes without telemetry without telemetry terms.
        common_routes: Compare over the routes every run holds instead of refusing runs whose
            route sets differ (``--common-routes``).
        fail_if_worse: Metrics of the gate (``--fail-if-worse``): check
            ``report["paired"]`` for a ``"worse"`` verdict on them (the CLI exits 5).
        bootstrap_samples: Resamples B. bootstrap_seed: The SplitMix64 seed.
        settings: Setting overrides, as for :func:`sds.score`.
        jobs: Worker threads.

    Returns:
        ``schema``, ``baseline``, ``models`` (mean and std over seeds), ``paired`` (``model``,
        ``metric``, ``n``, ``delta``, ``ci95``, ``p_better``, ``verdict``), ``flips``,
        ``scope``, ``routes`` (per route key, each model's values), ``config``, ``notes``,
        ``warnings``.

    Raises:
        ConfigError: Fewer than two models, a bad name in ``seeds`` or ``baseline``, an
            unknown metric, route sets that differ without ``common_routes``.
        InputError, IoError: A run's inputs, as for :func:`sds.score` (the message names the run).

    Example:
        >>> c = sds.compare({"base": "base/", "new": "new/"}, routes="bench2drive220.xml")
        >>> [p["verdict"] for p in c["paired"] if p["metric"] == "ds"]  # doctest: +SKIP
    """
    args: List[str] = []
    for name, run in runs.items():
        if isinstance(run, tuple):
            results, telemetry = run
            args.append(f"{name}={os.fspath(results)}")
            args += ["--telemetry-of", f"{name}={os.fspath(telemetry)}"]
        else:
            args.append(f"{name}={os.fspath(run)}")
    for model, names in (seeds or {}).items():
        args += ["--seeds", f"{model}={','.join(names)}"]
    if baseline is not None:
        args += ["--baseline", baseline]
    if routes is not None:
        args += ["--routes", os.fspath(routes)]
    if maps is not None:
        args += ["--maps", os.fspath(maps)]
    args += ["--profile", profile]
    if expected_routes is not None:
        args += ["--expected-routes", str(int(expected_routes))]
    if allow_missing_telemetry:
        args.append("--allow-missing-telemetry")
    if common_routes:
        args.append("--common-routes")
    if fail_if_worse:
        args += ["--fail-if-worse", ",".join(fail_if_worse)]
    args += ["--bootstrap-samples", str(int(bootstrap_samples))]
    args += ["--bootstrap-seed", str(int(bootstrap_seed))]
    for pair in _sds.settings_args(settings):
        args += ["--set", pair]
    if jobs is not None:
        args += ["--jobs", str(int(jobs))]
    report: Dict[str, Any] = json.loads(_sds.compare_json(args))
    return report
