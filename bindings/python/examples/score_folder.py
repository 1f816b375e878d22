"""Score a folder of Bench2Drive results and print the paper's numbers.

    python score_folder.py RESULTS_DIR TELEMETRY_DIR bench2drive220.xml
"""

from __future__ import annotations

import sys

import sds


def main(results: str, telemetry: str, routes: str) -> None:
    report = sds.score(results, telemetry=telemetry, routes=routes, expected_routes=220, progress=True)
    s = report["summary"]
    print(f"DS {s['driving_score']:.2f}  SR {s['success_rate']:.2f}  SDS {s['sds']}")
    for r in report["routes"]:
        if r["state"] != "ok":
            print(f"{r['route_id']}: {r['state']}")


if __name__ == "__main__":
    main(*sys.argv[1:4])
