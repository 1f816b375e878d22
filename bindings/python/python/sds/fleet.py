"""A fleet's vehicle logs scored on Ray: one task per batch of logs, the parts merged.

Each task runs ``sds score --mcap LOG ... --format json --output PART`` on its batch (where the
logs are: a worker of the cluster reads them from shared storage) and writes one part report;
the driver merges the parts with ``sds merge``. The merged report equals ``sds score`` over all
the logs on one machine in every field but ``inputs`` (the parts, against the logs: the
provenance lists the parts' digests) and ``warnings`` (each part's, prefixed by the part)
(docs/FLEET.md).

Ray is not a dependency of this package: :func:`score_logs_on_ray` imports it when called (it
starts a local cluster unless ``ray.init`` was called; pass ``address=`` to ``ray.init`` for a
real one). Example (a local cluster of 2 CPUs, batches of 50 logs)::

    from pathlib import Path
    import ray, sds.fleet
    ray.init(num_cpus=2)
    run = sds.fleet.score_logs_on_ray(sorted(Path("logs").glob("*.mcap")), "parts", batch=50)
    print(run.report["summary"]["mean_comfort"], run.merge.peak_rss_kib)

Each task's and the merge's peak resident memory is measured (``getrusage`` of its process),
so a campaign can size its workers.
"""

from __future__ import annotations

import importlib
import json
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Dict, List, Optional, Sequence, Tuple

from ._options import PathLike

__all__ = ["Step", "FleetRun", "batches", "score_batch", "merge_parts", "score_logs_on_ray"]


@dataclass(frozen=True)
class Step:
    """One process of the fleet: a batch's ``sds score`` or the ``sds merge``."""

    #: The report it wrote.
    output: Path
    #: The logs it scored (a batch) or the parts it merged.
    inputs: Tuple[Path, ...]
    #: Its exit status: 0, or 3 when the report has a problem route (the report is written).
    status: int
    #: Wall time, seconds.
    seconds: float
    #: Peak resident memory of its process, KiB (``ru_maxrss``).
    peak_rss_kib: int


@dataclass(frozen=True)
class FleetRun:
    """What :func:`score_logs_on_ray` did: the parts, the merge and the merged report."""

    #: One step per batch, in batch order.
    parts: Tuple[Step, ...]
    #: The merge of the parts.
    merge: Step
    #: The merged report (``sds merge --format json``), as a dict.
    report: Dict[str, Any]


def batches(logs: Sequence[PathLike], size: int) -> List[List[Path]]:
    """``logs`` cut into batches of ``size`` (the last one shorter), in order."""
    if size < 1:
        raise ValueError(f"batch size {size}: expected at least 1 log a batch")
    paths = [Path(p) for p in logs]
    return [paths[i : i + size] for i in range(0, len(paths), size)]


def _command(sds_bin: Optional[PathLike]) -> List[str]:
    # The package's own command by default: the same Rust code as the binary, run in-process.
    return [str(sds_bin)] if sds_bin is not None else [sys.executable, "-m", "sds"]


# Starts the command and writes its peak RSS (KiB) to the file argv[1]. A small process of its
# own: a child's ru_maxrss counts the memory of the process it was forked from until its exec
# (a Ray worker: 124 MB measured for an `sds score` of 30 MB), so the command is started from a
# fresh interpreter (-S -E: about 9 MB, the floor of what is measured) rather than the worker.
_MEASURE = """
import os, sys
pid = os.posix_spawnp(sys.argv[2], sys.argv[2:], os.environ)
_, status, usage = os.wait4(pid, 0)
with open(sys.argv[1], "w") as f:
    f.write(str(usage.ru_maxrss))
sys.exit(os.waitstatus_to_exitcode(status) % 256)
"""


def _run(cmd: List[str], output: Path, inputs: Sequence[Path]) -> Step:
    """Runs ``cmd`` and measures it; a failure (not 0 nor 3) raises with its message."""
    start = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="sds-fleet-") as tmp:
        rss_file = Path(tmp) / "maxrss"
        done = subprocess.run(
            [sys.executable, "-S", "-E", "-c", _MEASURE, str(rss_file), *cmd],
            stdin=subprocess.DEVNULL,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.PIPE,
            check=False,
        )
        seconds = time.perf_counter() - start
        rss = int(rss_file.read_text()) if rss_file.is_file() else 0
    if done.returncode not in (0, 3) or not output.is_file():
        message = done.stderr.decode("utf-8", "replace")
        raise RuntimeError(
            f"{' '.join(cmd[:4])} ... exited with {done.returncode} writing {output}:\n{message}"
        )
    return Step(output, tuple(inputs), done.returncode, seconds, rss)


def score_batch(
    logs: Sequence[PathLike],
    part: PathLike,
    *,
    topics: Sequence[str] = (),
    settings: Sequence[str] = (),
    sds_bin: Optional[PathLike] = None,
) -> Step:
    """One task's work: ``sds score --mcap`` over ``logs``, its JSON report written to ``part``.

    ``topics`` are ``--topic NAME=TOPIC`` values (e.g. ``"event=/events"``), ``settings``
    ``--set NAME=VALUE`` values; every batch of a run must take the same (``sds merge`` refuses
    parts scored with different settings). ``sds_bin``: the ``sds`` binary to run (default:
    this package's ``python -m sds``).
    """
    paths = [Path(p) for p in logs]
    out = Path(part)
    cmd = _command(sds_bin) + ["score"]
    for log in paths:
        cmd += ["--mcap", str(log)]
    for t in topics:
        cmd += ["--topic", t]
    for s in settings:
        cmd += ["--set", s]
    cmd += ["--format", "json", "--output", str(out)]
    return _run(cmd, out, paths)


def merge_parts(
    parts: Sequence[PathLike], merged: PathLike, *, sds_bin: Optional[PathLike] = None
) -> Step:
    """``sds merge`` of ``parts`` into ``merged`` (JSON), measured."""
    paths = [Path(p) for p in parts]
    out = Path(merged)
    cmd = _command(sds_bin) + ["merge"] + [str(p) for p in paths]
    cmd += ["--format", "json", "--output", str(out)]
    return _run(cmd, out, paths)


def score_logs_on_ray(
    logs: Sequence[PathLike],
    out_dir: PathLike,
    *,
    batch: int = 100,
    topics: Sequence[str] = (),
    settings: Sequence[str] = (),
    sds_bin: Optional[PathLike] = None,
    task_cpus: float = 1.0,
    timeout: Optional[float] = None,
) -> FleetRun:
    """Scores ``logs`` as Ray tasks, one per batch of ``batch`` logs, and merges the parts.

    Writes ``out_dir/part-00000.json``, ... (one per batch) and ``out_dir/merged.json``; returns
    the steps and the merged report. Each task asks Ray for ``task_cpus`` CPUs (``sds score``
    scores one log at a time per thread: ``--set threads=N`` with ``task_cpus=N``). ``timeout``
    bounds the wait for the tasks, in seconds. ``topics``, ``settings``, ``sds_bin``: as
    :func:`score_batch` (a path every worker can run).

    Raises ``ImportError`` without Ray, ``RuntimeError`` naming the batch's command and its
    message when a task's ``sds score`` fails, and ``ray``'s errors when a task is lost.
    """
    ray: Any = importlib.import_module("ray")
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    cut = batches(logs, batch)
    if not cut:
        raise ValueError("no logs to score")
    task = ray.remote(num_cpus=task_cpus)(score_batch)
    refs = [
        task.remote(
            b,
            out / f"part-{i:05d}.json",
            topics=list(topics),
            settings=list(settings),
            sds_bin=sds_bin,
        )
        for i, b in enumerate(cut)
    ]
    parts: List[Step] = ray.get(refs, timeout=timeout)
    merged = merge_parts([p.output for p in parts], out / "merged.json", sds_bin=sds_bin)
    report: Dict[str, Any] = json.loads(merged.output.read_text(encoding="utf-8"))
    return FleetRun(tuple(parts), merged, report)
