"""Runs Bench2Drive's own comfort script on a run, in one process, for `bench/run.sh`.

Usage: python b2d_smoothness.py SCRIPT RESULTS TELEMETRY

SCRIPT is Bench2Drive's `tools/efficiency_smoothness_benchmark.py` from a checkout of
Bench2Drive (its licence, CC BY-NC-ND, forbids copying it here: it is never part of this
repository). Its two functions are called as its own `__main__` calls them: `read_from_json`
(reads every route's `metric_info.json`) and `seg_compute_comfort_metric` per route; the
smoothness is printed as the script prints it. The driver exists only because the script's last
line divides by the number of routes with a min-speed infraction, and raises on a run that has
none (the generated runs have none); the comfort work is all done before that line.
"""

import importlib.util
import sys


def main() -> None:
    script, results, telemetry = sys.argv[1:4]
    spec = importlib.util.spec_from_file_location("b2d_smoothness_script", script)
    if spec is None or spec.loader is None:
        sys.exit(f"cannot load {script}")
    b2d = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(b2d)
    all_data, efficiency = b2d.read_from_json(results, telemetry)
    comfort = [b2d.seg_compute_comfort_metric(**record) for record in all_data]
    if efficiency:
        print(f"Driving Efficiency={sum(efficiency) / len(efficiency)}")
    print(f"Driving Smoothness={sum(comfort) / len(comfort)}")


if __name__ == "__main__":
    main()
