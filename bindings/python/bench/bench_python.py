"""Benchmarks of the Python package (numbers recorded in docs/PERFORMANCE.md).

1. `Monitor.push` with a `get_metric_info()`-shaped dict: the cost per tick (goal < 5 us).
2. `sds.score` throughput against the `sds` binary on the same run (goal: within 5 %).

    python bench/bench_python.py SDS_BIN RUN_DIR     # RUN_DIR from `sds demo --large RUN_DIR`
"""

from __future__ import annotations

import json
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path
from typing import Any, Dict, List

import sds


def ticks(n: int) -> List[Dict[str, Any]]:
    """A route of n ticks shaped like Bench2Drive's get_metric_info(): cruising with a weave."""
    out = []
    for i in range(n):
        out.append({
            "acceleration": [0.3 + 0.01 * (i % 17), 0.2 * ((i % 40) - 20) / 20, 9.81],
            "angular_velocity": [0.0, 0.0, 3.0 * ((i % 40) - 20) / 20],
            "forward_vector": [1.0, 0.0, 0.0],
            "right_vector": [0.0, 1.0, 0.0],
            "location": [100.0 + 0.4 * i, 50.0 + 0.05 * (i % 40), 0.0],
            "rotation": [0.0, 0.0, 0.0],
        })
    return out


def bench_push(n: int = 4000, repeats: int = 15) -> None:
    data = ticks(n)
    route = [(100.0 + 2.0 * k, 50.0) for k in range(n // 4)]
    for label, kwargs in (("push(entry)", {}), ("push(entry), Monitor(route=...)", {"route": route})):
        per_tick = []
        for _ in range(repeats):
            m = sds.Monitor(**kwargs)
            t0 = time.perf_counter()
            for entry in data:
                m.push(entry)
            per_tick.append((time.perf_counter() - t0) / n * 1e6)
            m.finish()
        print(f"{label:<34} median {statistics.median(per_tick):.2f} us/tick, "
              f"min {min(per_tick):.2f} (n={n}, {repeats} routes)")


def bench_score(sds_bin: str, run: Path, repeats: int = 5) -> None:
    """Wall and CPU time (user + sys, all threads) of both, alternated, medians."""
    args = ["--results", str(run / "results.json"), "--telemetry", str(run / "telemetry"),
            "--routes", str(run / "routes.xml")]
    cli_wall, cli_cpu, py_wall, py_cpu = [], [], [], []
    out = run / "bench-report.json"
    report: Dict[str, Any] = {}
    for _ in range(repeats):
        r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
        t0 = time.perf_counter()
        subprocess.run([sds_bin, "score", *args, "--format", "json", "-o", str(out)], check=True)
        cli_wall.append(time.perf_counter() - t0)
        r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
        cli_cpu.append(r1.ru_utime - r0.ru_utime + r1.ru_stime - r0.ru_stime)
        c0, t0 = time.process_time(), time.perf_counter()
        report = sds.score(run / "results.json", telemetry=run / "telemetry", routes=run / "routes.xml")
        py_wall.append(time.perf_counter() - t0)
        py_cpu.append(time.process_time() - c0)
    assert report == json.loads(out.read_text())
    frames = sum(r["frames"] for r in report["routes"])
    med = statistics.median
    print(f"{len(report['routes'])} routes, {frames} frames, {repeats} runs each, alternated; medians")
    for name, wall, cpu in (("sds score (binary)", cli_wall, cli_cpu), ("sds.score (Python)", py_wall, py_cpu)):
        print(f"{name:<20} wall {med(wall):.3f} s  cpu {med(cpu):.3f} s  "
              f"({frames / med(cpu) / 1e6:.3f} M frames per CPU-second)")
    print(f"ratio Python / binary: wall {med(py_wall) / med(cli_wall):.3f}, cpu {med(py_cpu) / med(cli_cpu):.3f}")


if __name__ == "__main__":
    bench_push()
    if len(sys.argv) == 3:
        bench_score(sys.argv[1], Path(sys.argv[2]))
