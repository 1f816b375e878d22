#!/usr/bin/env bash
# A fleet on Ray and the merge at scale (issue 51 goal 3). Not part of CI. Three measurements:
#   1. LOGS vehicle logs (default 2,000, MCAP, written by scripts/fleet_logs.py with the project's
#      writer) scored by sds.fleet.score_logs_on_ray on a local Ray cluster of CPUS CPUs, BATCH
#      logs a task: wall time, each task's peak RSS (max and median), the merge's time and peak
#      RSS; then `sds score` over every log on one machine (time, peak RSS) and the check that
#      the merged report equals it but for `inputs` and `warnings`;
#   2. `sds merge` of LOGS one-route parts (one `sds score --mcap` per log): time, peak RSS;
#   3. `sds merge --duplicates all` of PARTS220 parts (default 1,000) of one 220-route run
#      (`sds demo --large --large-routes 220 --large-frames 200`, scored with its route XML, hard
#      links to one report: 220,000 rows merged): time, peak RSS, merged report size.
#
# Usage: bench/fleet.sh SDS [PYTHON]
#   SDS     the sds binary (the tasks and merges run it)
#   PYTHON  a Python with the sds package, ray, mcap and mcap-ros2-support (default: the test
#           venv bindings/python/run-tests.sh makes, target/py-test/bin/python)
# Environment: BENCH_DIR (default target/bench-fleet; never committed), LOGS, BATCH (100), CPUS
# (2), PARTS220 (1000).
set -euo pipefail
cd "$(dirname "$0")/.."
SDS=$(realpath "${1:?usage: bench/fleet.sh SDS [PYTHON]}")
PY=${2:-target/py-test/bin/python}
OUT=$(realpath -m "${BENCH_DIR:-target/bench-fleet}")
LOGS=${LOGS:-2000}
BATCH=${BATCH:-100}
CPUS=${CPUS:-2}
PARTS220=${PARTS220:-1000}
mkdir -p "$OUT"
"$PY" -c 'import ray, mcap_ros2.writer, sds.fleet' \
    || { echo "fleet.sh: $PY lacks ray, mcap-ros2-support or sds.fleet (run bindings/python/run-tests.sh)" >&2; exit 2; }
mb() { awk "BEGIN { printf \"%.1f\", $1 / 1024 }"; }

echo "## 1. $LOGS logs on Ray ($CPUS CPUs, $BATCH logs a task)"
rm -rf "$OUT/logs" "$OUT/parts"
"$PY" scripts/fleet_logs.py "$SDS" "$OUT/logs" "$LOGS" >/dev/null
"$PY" - "$SDS" "$OUT" "$BATCH" "$CPUS" <<'EOF'
import json, statistics, sys, tempfile, time
from pathlib import Path
import ray, sds.fleet
sds_bin, out, batch, cpus = sys.argv[1], Path(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
logs = sorted((out / "logs").glob("*.mcap"))
ray.init(num_cpus=cpus, include_dashboard=False, log_to_driver=False,
         _temp_dir=tempfile.mkdtemp(prefix="sds-ray-"))
start = time.perf_counter()
run = sds.fleet.score_logs_on_ray(logs, out / "parts", batch=batch, sds_bin=sds_bin,
                                  topics=["path=/path", "event=/events"])
wall = time.perf_counter() - start
ray.shutdown()
rss = sorted(p.peak_rss_kib for p in run.parts)
print(f"ray: {len(logs)} logs, {len(run.parts)} tasks: {wall:.1f} s wall (merge included); "
      f"task peak RSS max {rss[-1] / 1024:.1f} MB, median {statistics.median(rss) / 1024:.1f} MB; "
      f"task time median {statistics.median(p.seconds for p in run.parts):.2f} s")
print(f"merge of {len(run.parts)} parts: {run.merge.seconds:.2f} s, peak RSS "
      f"{run.merge.peak_rss_kib / 1024:.1f} MB")
EOF
args=()
for l in "$OUT"/logs/*.mcap; do args+=(--mcap "$l"); done
read -r k s < <(/usr/bin/time -f '%M %e' "$SDS" score "${args[@]}" --topic path=/path \
    --topic event=/events --format json -o "$OUT/whole.json" 2>&1 >/dev/null | tail -n1)
echo "one machine: sds score over the $LOGS logs: $s s, peak RSS $(mb "$k") MB"
"$PY" - "$OUT" <<'EOF'
import json, sys
from pathlib import Path
out = Path(sys.argv[1])
a, b = (json.loads((out / f).read_text()) for f in ("parts/merged.json", "whole.json"))
drop = lambda r: {k: v for k, v in r.items() if k not in ("inputs", "warnings")}
assert drop(a) == drop(b), "the merged report differs from the one-machine score"
print("merged == one-machine score (but inputs, warnings)")
EOF

echo "## 2. merge of $LOGS one-route parts"
mkdir -p "$OUT/one"
ls "$OUT"/logs/*.mcap | xargs -P "$CPUS" -I{} sh -c \
    'f={}; n=$(basename "$f" .mcap); [ -f "$0/one/$n.json" ] || "$1" score --mcap "$f" --topic path=/path --topic event=/events --format json -o "$0/one/$n.json" 2>/dev/null || [ $? = 3 ]' "$OUT" "$SDS"
read -r k s < <(/usr/bin/time -f '%M %e' "$SDS" merge "$OUT"/one/*.json -o "$OUT/merged-one.json" 2>&1 >/dev/null | tail -n1)
echo "merge of $(ls "$OUT"/one/*.json | wc -l) one-route parts: $s s, peak RSS $(mb "$k") MB"

echo "## 3. merge of $PARTS220 parts of 220 routes (--duplicates all)"
if [[ ! -f $OUT/r220/.done ]]; then
    "$SDS" demo "$OUT/r220" --large --large-routes 220 --large-frames 200 --force >/dev/null 2>&1
    touch "$OUT/r220/.done"
fi
"$SDS" score --results "$OUT/r220/results.json" --telemetry "$OUT/r220/telemetry" \
    --routes "$OUT/r220/routes.xml" --format json -o "$OUT/p220.json" 2>/dev/null || [[ $? == 3 ]]
rm -rf "$OUT/p220s" && mkdir -p "$OUT/p220s"
for i in $(seq -w 1 "$PARTS220"); do ln "$OUT/p220.json" "$OUT/p220s/part-$i.json"; done
read -r k s < <(/usr/bin/time -f '%M %e' "$SDS" merge "$OUT"/p220s/*.json --duplicates all \
    -o "$OUT/merged-220.json" 2>&1 >/dev/null | tail -n1)
echo "merge of $PARTS220 parts of 220 routes ($(mb $(($(stat -c %s "$OUT/p220.json") / 1024))) MB each): $s s, peak RSS $(mb "$k") MB, merged report $(mb $(($(stat -c %s "$OUT/merged-220.json") / 1024))) MB"
