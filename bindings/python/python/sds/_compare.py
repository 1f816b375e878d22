"""``sds.compare``: runs compared against a baseline (docs/SCORE.md §10.3), from Python."""

from __future__ import annotations

import os
from typing import Any, Callable, Dict, List, Literal, Mapping, Optional, Sequence, Tuple, Union

from . import _sds
from ._options import PathLike, run_options
from ._sds import ConfigError
from ._warn import warn_each

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
    protocols: Optional[Sequence[str]] = None,
    rank: bool = False,
    repro_halfwidth: float = 1.0,
    progress: Optional[Callable[[int, int], Any]] = None,
    route_subset: Optional[Literal["all", "found"]] = None,
    sweep: Optional[Mapping[str, Sequence[Union[str, int, float, bool]]]] = None,
) -> Dict[str, Any]:
    """Compares runs route by route; returns the ``sds-compare/1`` report as a dict.

    The library is called directly (no command line in between) and the report converted to
    Python objects as ``json.loads`` would read ``sds compare --format json``. Each run is
    scored as :func:`sds.score` would; models (a run, or the seeds of one model)
    are compared with the baseline on the routes' paired differences, with a bootstrap interval
    and a verdict per metric (``ds``, ``success``, ``ds_safe``, ``comfort``).

    Args:
        runs: Run name -> results (file or folder; telemetry looked for beside it) or
            ``(results, telemetry)``. In order: the first model is the baseline.
        seeds: Model name -> the names of its runs (``--seeds``). Runs are grouped only here.
        baseline: The baseline model (``--baseline``; default the first).
        routes: The route XML every run is scored against (``--routes``).
        maps: A folder of OpenDRIVE maps (``--maps``).
        profile: ``"physical"``, ``"b2d-legacy"`` or ``"autoware"``.
        expected_routes: The benchmark's size N (``--expected-routes``).
        allow_missing_telemetry: Score routes without telemetry without telemetry terms.
        common_routes: Compare over the routes every run holds instead of refusing runs whose
            route sets differ (``--common-routes``).
        fail_if_worse: Metrics of the gate (``--fail-if-worse``): check
            ``report["paired"]`` for a ``"worse"`` or ``"no data"`` verdict on them (the CLI
            exits 5 on either: a gate never passes by checking nothing).
        bootstrap_samples: Resamples B, 1000 to 1000000 (and n x B at most 250 million per
            model and metric). bootstrap_seed: The SplitMix64 seed; each model and metric
            draws from its own generator seeded with it.
        settings: Setting overrides, as for :func:`sds.score`.
        jobs: Worker threads.
        protocols: Also score every run's routes under these scoring protocols, as for
            :func:`sds.score` (``--protocol``; ids, or ``["all"]``); the paired comparison
            stays on ``ds``, ``success``, ``ds_safe``, ``comfort``.
        rank: Rank every model by its mean DS over the compared routes (``--rank``): the
            report's ``ranking`` lists, by rank (ties by name), each model's ``mean_ds``,
            ``rank``, ``rank_ci95`` (95 % bootstrap interval of its rank, one generator seeded
            with ``bootstrap_seed``) and ``p_best`` (share of resamples where it ranks first).
        repro_halfwidth: h of each model's ``seeds_needed`` (``--repro-halfwidth``): the seeds
            for a 95 % interval of its mean DS no wider than +-h DS points (above 0).
        route_subset: Which routes of ``routes`` make each run's route set
            (``--route-subset``): ``"all"`` (a route without a record counts as 0) or
            ``"found"`` (those with a record), as for :func:`sds.score`. None: the setting
            ``route_subset`` (default ``"all"``, or from ``settings``).
        progress: Called with ``(done, total)`` after each route of the run being scored (the
            count starts again with each run); an exception it raises stops the comparison
            between routes and is raised here.
        sweep: Setting name -> its values (``--sweep NAME=V1,V2,...``): every model is scored
            at every point of the grid (the product of the lists, at most 64 points; a setting
            that changes a route's figures, e.g. ``{"critical_excess": [0.5, 0.65, 0.8]}``).
            The report's ``sweep`` holds ``settings``, ``points`` (each point's ``values`` and
            every model's ``ds_safe``, ``comfort``, ``sds``, ``rank``), ``pairs`` (``a``,
            ``b``, ``order_stable``, ``flips``: point indices) and ``ranges`` (each model's
            ``sds_min``, ``sds_max``).

    Returns:
        ``schema``, ``baseline``, ``models`` (mean and std over seeds), ``paired`` (``model``,
        ``metric``, ``n``, ``delta``, ``ci95``, ``p_better``, ``verdict``), ``flips``,
        ``scope``, ``routes`` (per route key, each model's values), ``config``, ``notes``,
        ``warnings``; each model also has its seeds' figures (``routes`` with ``ds_mean``,
        ``ds_std``, ``ds_min``, ``ds_max``, ``success_share`` per route, ``flaky_routes``,
        ``seed_ds``, ``seed_std``, ``seeds_needed``), with ``rank`` the report has
        ``ranking``, and with ``sweep`` it has ``sweep``.

    Warns:
        SdsWarning: Each warning ``sds compare`` prints: each run's report's (``"<run>: ..."``;
            a missing map per run, where the command says it once), then the comparison's own
            ``warnings``, at the caller's line.

    Raises:
        ConfigError: A ``sweep`` setting that does not exist or changes no route's figures
            (the message lists those that do), a value it refuses, more than 64 points;
            fewer than two models, a bad name in ``seeds`` or ``baseline``, an
            unknown metric, route sets that differ without ``common_routes``,
            ``bootstrap_samples`` out of range, a ``repro_halfwidth`` not above 0; an invalid
            ``profile``, ``settings`` or ``protocols``.
        InputError, IoError: A run's inputs, as for :func:`sds.score` (the message names the run).
        KeyboardInterrupt: Ctrl-C, which stops the comparison between routes, runs and
            bootstrap blocks.

    Example:
        >>> c = sds.compare({"base": "base/", "new": "new/"}, routes="bench2drive220.xml")
        >>> [p["verdict"] for p in c["paired"] if p["metric"] == "ds"]  # doctest: +SKIP
        >>> c = sds.compare({"ep10": "ep10/", "ep20": "ep20/", "ep30": "ep30/"}, rank=True)
        >>> [(r["model"], r["rank"], r["rank_ci95"]) for r in c["ranking"]]  # doctest: +SKIP
        >>> c = sds.compare({"a": "a/", "b": "b/"}, sweep={"critical_excess": [0.5, 0.65]})
        >>> [p["order_stable"] for p in c["sweep"]["pairs"]]  # doctest: +SKIP
    """
    if isinstance(fail_if_worse, str):
        raise ConfigError(
            f"fail_if_worse={fail_if_worse!r}: expected a list of metrics, e.g. ['ds']"
        )
    for name, values in (sweep or {}).items():
        if isinstance(values, (str, bytes)):
            raise ConfigError(
                f"sweep[{name!r}]={values!r}: expected a list of values, e.g. [0.5, 0.65]"
            )
    pairs: List[Tuple[str, str, Optional[str]]] = []
    for name, run in runs.items():
        if isinstance(run, tuple):
            results, telemetry = run
            pairs.append((name, os.fspath(results), os.fspath(telemetry)))
        else:
            pairs.append((name, os.fspath(run), None))
    options: Dict[str, Any] = {
        # The options every scored run shares (as for sds.score; no `duplicates` option, as
        # `sds compare` has none: the setting's default, or `settings={"duplicates": ...}`).
        **run_options(
            profile=profile,
            duplicates=None,
            expected_routes=expected_routes,
            allow_missing_telemetry=allow_missing_telemetry,
            settings=settings,
            jobs=jobs,
            protocols=protocols,
            route_subset=route_subset,
        ),
        # The comparison's own.
        "seeds": [(model, list(names)) for model, names in (seeds or {}).items()],
        "baseline": baseline,
        "routes": None if routes is None else os.fspath(routes),
        "maps": None if maps is None else os.fspath(maps),
        "common_routes": common_routes,
        "fail_if_worse": list(fail_if_worse or []),
        "bootstrap_samples": int(bootstrap_samples),
        "bootstrap_seed": int(bootstrap_seed),
        "rank": bool(rank),
        "repro_halfwidth": float(repro_halfwidth),
        "progress": progress,
        "sweep": None if sweep is None else {k: list(v) for k, v in sweep.items()},
    }
    report, warned = _sds.compare(pairs, options)
    warn_each(warned)
    return report
