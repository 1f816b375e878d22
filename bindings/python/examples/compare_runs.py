"""Compare two runs route by route: where does DS_safe differ, and why?

    python compare_runs.py RESULTS_A TELEMETRY_A RESULTS_B TELEMETRY_B bench2drive220.xml
"""

from __future__ import annotations

import sys
from typing import Any, Dict

import sds


def by_route(report: Dict[str, Any]) -> Dict[str, Dict[str, Any]]:
    return {r["route_id"]: r for r in report["routes"] if r["route_id"]}


def main(results_a: str, telemetry_a: str, results_b: str, telemetry_b: str, routes: str) -> None:
    a = sds.score(results_a, telemetry=telemetry_a, routes=routes)
    b = sds.score(results_b, telemetry=telemetry_b, routes=routes)
    for name in ("driving_score", "mean_ds_safe", "mean_comfort", "sds"):
        print(f"{name:>14}: {a['summary'][name]}  vs  {b['summary'][name]}")
    ra, rb = by_route(a), by_route(b)
    for rid in sorted(ra.keys() & rb.keys()):
        x, y = ra[rid], rb[rid]
        if x["ds_safe"] != y["ds_safe"]:
            print(f"{rid}: DS_safe {x['ds_safe']} vs {y['ds_safe']} "
                  f"(nodecel {x['collisions']['nodecel']}/{y['collisions']['nodecel']}, "
                  f"comfort {x['comfort']['score']}/{y['comfort']['score']})")


if __name__ == "__main__":
    main(*sys.argv[1:6])
