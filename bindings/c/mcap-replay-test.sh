#!/usr/bin/env bash
# The C API on vehicle logs (docs/SCORE.md §2.4, issue 39): every demo route's telemetry written as a
# ROS 2 MCAP log by an independent writer (scripts/telemetry_to_mcap.py: Python mcap +
# mcap-ros2-support), its frames made by `sds frames --mcap`, replayed by the C example
# `sds_replay`, gives the same lines as the route's telemetry frames replayed by `sds_replay`:
# every comfort, lateral and collision verdict and the summary. The one difference allowed is a
# collision's kind (a log's event is "an event": collisions_vehicle), masked before the diff.
#
# Usage: mcap-replay-test.sh SDS SDS_REPLAY DEMO_DIR OUT_DIR   (run-tests.sh calls it after step 4)
set -euo pipefail
SDS=$1 REPLAY=$2 DEMO=$3 OUT=$4
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
PY="${CARGO_TARGET_DIR:-$ROOT/target}/py-tools/bin/python"
say() { printf '[c-api] %s\n' "$*"; }
fail() {
  printf '[c-api] FAILED: %s\n' "$*" >&2
  exit 1
}
if ! "$PY" -c 'import mcap_ros2.writer' 2>/dev/null; then
  why="$PY cannot import mcap_ros2: the C API is not tested on vehicle logs (bash scripts/setup.sh installs mcap and mcap-ros2-support; by hand: $PY -m pip install mcap==1.6.0 mcap-ros2-support==0.6.0)"
  printf '\n[c-api] ##################################################################\n[c-api] SKIPPED: %s\n[c-api] ##################################################################\n\n' "$why" >&2
  if [ -n "${SDS_SKIP_LOG:-}" ]; then printf 'c-api mcap: %s\n' "$why" >>"$SDS_SKIP_LOG"; fi
  exit 0
fi
mkdir -p "$OUT"
"$SDS" score --results "$DEMO/results.json" --telemetry "$DEMO/telemetry" --routes "$DEMO/routes.xml" \
  --format json -o "$OUT/demo.json" 2>/dev/null || true
mask() { sed -E 's/"collisions":\{"pedestrian":[0-9]+,"vehicle":[0-9]+,"layout":[0-9]+,"workzone":[0-9]+\}/"collisions":K/' "$1"; }
n=0
while IFS=$'\t' read -r id dt steps path; do
  t=$(ls -d "$DEMO/telemetry/${id}"_*)
  ev=()
  [ "$steps" = "-" ] || ev=(--events "$steps")
  "$PY" "$ROOT/scripts/telemetry_to_mcap.py" "$t/metric_info.json" "$OUT/$id.mcap" --dt "$dt" \
    --path "$path" "${ev[@]}" || fail "$id: writing the MCAP log"
  "$SDS" frames --results "$DEMO/results.json" --telemetry "$DEMO/telemetry" --routes "$DEMO/routes.xml" \
    --route-id "$id" -o "$OUT/telemetry-$id.jsonl"
  "$SDS" frames --mcap "$OUT/$id.mcap" --topic path=/path --topic event=/events --set "dt=$dt" \
    -o "$OUT/mcap-$id.jsonl" 2>/dev/null
  "$REPLAY" "$OUT/telemetry-$id.jsonl" >"$OUT/c-telemetry-$id.txt" || fail "$id: sds_replay on the telemetry frames"
  "$REPLAY" "$OUT/mcap-$id.jsonl" >"$OUT/c-mcap-$id.txt" || fail "$id: sds_replay on the log's frames"
  diff -u <(mask "$OUT/c-telemetry-$id.txt") <(mask "$OUT/c-mcap-$id.txt") >&2 \
    || fail "$id: the C replay of the MCAP log's frames differs from the telemetry's"
  n=$((n + 1))
done < <(python3 - "$OUT/demo.json" "$DEMO/routes.xml" <<'PY'
import json, sys, xml.etree.ElementTree as ET
xml = {r.get("id"): r for r in ET.parse(sys.argv[2]).getroot()}
for r in json.load(open(sys.argv[1]))["routes"]:
    rid = r["route_id"]
    route = xml[rid[len("RouteScenario_"):].split("_rep")[0]]
    path = ";".join(f"{p.get('x')},{p.get('y')},{p.get('z')}" for p in route.iter("position"))
    steps = ",".join(str(e["step"]) for e in r["collision_events"] if e.get("step") is not None)
    print(f"{rid}\t{r['dt']}\t{steps or '-'}\t{path}")
PY
)
[ "$n" -gt 0 ] || fail "no demo route was checked"
say "ok: $n demo routes as MCAP logs (independent writer) replayed by sds_replay: the same verdicts and summaries as their telemetry"
