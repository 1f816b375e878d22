#!/usr/bin/env python3
"""End-to-end cost of the maps: `sds score --jobs 1` on a `sds demo --large` run without a map,
with its town map (`lateral_reference=route`) and with `lateral_reference=lane`; prints the best
CPU time (user + system, of the child process) of N runs each and the MB/s per core.

    target/release/sds demo --large --large-routes 44 target/bench-run/maps44
    python3 bench/map_overhead.py target/release/sds target/bench-run/maps44 7
"""
import os
import resource
import subprocess
import sys


def main() -> None:
    sds, run, repeat = sys.argv[1], sys.argv[2], int(sys.argv[3]) if len(sys.argv) > 3 else 5
    base = [sds, "score", "--results", f"{run}/results.json", "--telemetry", f"{run}/telemetry",
            "--routes", f"{run}/routes.xml", "--format", "json", "--jobs", "1"]
    variants = {
        "no map": [],
        "map, route": ["--maps", f"{run}/maps"],
        "map, lane": ["--maps", f"{run}/maps", "--set", "lateral_reference=lane"],
    }
    best: dict = {}
    for _ in range(repeat):
        for name, extra in variants.items():
            r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
            subprocess.run(base + extra, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                           check=True)
            r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
            cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
            best[name] = min(best.get(name, float("inf")), cpu)
    mb = sum(os.path.getsize(os.path.join(d, f))
             for d, _, fs in os.walk(f"{run}/telemetry") for f in fs) / 1e6
    for name, cpu in best.items():
        extra = (cpu / best["no map"] - 1) * 100
        print(f"{name:12} {cpu:.3f} s CPU  {mb / cpu:5.0f} MB/s per core  ({mb:.0f} MB)  {extra:+.1f} %")


if __name__ == "__main__":
    main()
