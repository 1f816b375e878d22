"""``sds.watch``: the score of an evaluation while it runs (docs/USAGE.md §8), from Python."""

from __future__ import annotations

from typing import Any, Callable, Dict, Literal, Mapping, Optional, Sequence, Union

from . import _sds
from ._options import PathLike, run_options
from ._options import paths as _paths
from ._sds import Watch


def watch(
    results: Union[PathLike, Sequence[PathLike]],
    *,
    telemetry: Optional[PathLike] = None,
    routes: Optional[PathLike] = None,
    maps: Optional[PathLike] = None,
    interval: float = 10.0,
    timeout: Optional[float] = None,
    profile: str = "physical",
    duplicates: str = "error",
    expected_routes: Optional[int] = None,
    allow_missing_telemetry: bool = False,
    settings: Optional[Mapping[str, Union[str, int, float, bool]]] = None,
    group_by: Optional[str] = None,
    labels: Optional[PathLike] = None,
    jobs: Optional[int] = None,
    protocols: Optional[Sequence[str]] = None,
    on_round: Optional[Callable[[Dict[str, Any], Dict[str, Any]], Any]] = None,
    route_subset: Optional[Literal["all", "found"]] = None,
    stall_factor: Optional[float] = None,
) -> Watch:
    """Watches an evaluation while it runs; returns an iterator of partial reports.

    The library's watch of ``sds watch`` (no command line in between), one round per
    ``next()``: the inputs read again, each route replayed again only when its record or its
    telemetry changed, the report made. Each report is a dict of the same shape as
    :func:`sds.score`'s (routes without a record yet are ``missing``); the figures of the round
    that made it are in the iterator's ``status`` dict:

    - ``round``: the round's number (rounds retried on a half-written file count too);
      ``time``: when it ran (UTC, ``2026-11-27T17:45:33Z``);
    - ``done``, ``n``: routes with a record, and the benchmark's size N;
    - ``ds_done``, ``sds_done``: DS and SDS over the routes done; ``ds_n``, ``sds_n``: over N,
      the routes not done counting 0 (the two "so far" figures of the status line);
    - ``last_route``, ``last_state``, ``last_ds``: the last route replayed (else the last with a
      record), its state and DS;
    - ``crashes``: routes whose record says the run broke, the rerun list's classes but
      ``missing`` and ``timeout`` (a ``Failed - TickRuntime`` route is not a crash);
    - ``complete``: every route of the set has a record (a route XML or ``expected_routes``
      gives the set; without one, every checkpoint's ``progress`` says done);
    - ``seconds_left``: the routes' mean ``meta.duration_system`` times the routes left, or None
      (no usable duration: negative ones are left out; or every shard done with routes left);
    - ``changed``, ``rescored``, ``reused``, ``rescored_routes``: whether anything changed since
      the previous report, the routes replayed (and their ids) and those taken from the cache;
    - ``retries``: rounds since the previous report that caught a results file half-written
      (retried, never raised); ``round_ms``: the round's time;
    - ``stopped``: None, or why the iterator stopped (``"complete"``, ``"timeout"``).

    These are the fields of ``sds watch --status-json``, one schema for both.

    The first ``next()`` scores at once; each later one first sleeps ``interval`` seconds (and
    again after a retried round). The iterator stops once the route set is complete and one
    more round found nothing new, or when ``timeout`` seconds have passed since the first
    ``next()`` (after one last round, yielded if it found something new). The last report is
    then :func:`sds.score`'s over the same files. The GIL is released while sleeping and
    scoring; Ctrl-C (any Python signal) raises from ``next()`` within 50 ms of the sleep, or
    when the round under way ends.

    Args:
        results: Evaluator results as for :func:`sds.score`: a checkpoint the evaluator
            rewrites in place, a folder of shard checkpoints or of per-route folders, or a list.
        telemetry, routes, maps: As for :func:`sds.score`.
        interval: Seconds between rounds (fractions allowed; ``--interval``).
        timeout: Stop after this many seconds (``--timeout``); None: until complete.
        profile, duplicates, expected_routes, allow_missing_telemetry, settings, group_by,
            labels, jobs, protocols, route_subset: As for :func:`sds.score`.
        on_round: Called with ``(status, report)`` for each report the iterator yields, before
            it is yielded (an exception it raises comes out of ``next()``); e.g. a
            :class:`sds.Tracker`'s ``on_round``, which logs the round to W&B, TensorBoard or
            MLflow.
        stall_factor: K of the stalled-shard rule (``--stall-factor``): a shard is said stalled
            after K times its median route time without a new record; None: the default, 5.

    Returns:
        The iterator (its ``status`` property: the figures above; ``finished``: True once it
        stopped).

    Raises:
        ConfigError: An invalid option, as :func:`sds.score`, an ``interval`` not in
            (0, 86400] or a ``timeout`` not in [0, 31536000] seconds (at once). From ``next()``,
            at once, the errors no later write of the evaluator can mend, as :func:`sds.score`
            raises them: an invalid setting, route XML or label file (a missing one, a null
            label), duplicate route ids, a ``telemetry`` or ``maps`` folder that does not exist,
            a results file that is not JSON from its first byte. A results file that ends early,
            shrank or is not there yet is retried, never raised; one still half-written at the
            timeout gives a ``RuntimeWarning``.

    Example:
        >>> w = sds.watch("eval/results.json", telemetry="eval/", routes="bench2drive220.xml",
        ...               interval=30)  # doctest: +SKIP
        >>> for report in w:  # doctest: +SKIP
        ...     s = w.status
        ...     print(f"{s['done']}/{s['n']} routes, SDS {s['sds_done']} so far")
        >>> report == sds.score("eval/results.json", telemetry="eval/",
        ...                     routes="bench2drive220.xml")  # doctest: +SKIP
        True
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
        "interval": float(interval),
        "timeout": None if timeout is None else float(timeout),
        "group_by": group_by,
        "labels": labels,
        "on_round": on_round,
        "stall_factor": None if stall_factor is None else float(stall_factor),
    }
    return _sds.watch(_paths(results), options)
