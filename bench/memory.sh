#!/usr/bin/env bash
# Peak RSS of `sds score --jobs 1` against the number of routes (issue 51 goal 1), side by side
# with another binary (main's, built into a separate target dir first). Not part of CI.
#
# Usage: bench/memory.sh NEW_SDS [OLD_SDS]
# Environment:
#   BENCH_DIR  where generated runs go (default: target/bench-memory); never committed
#   ROUTES     route counts of the series (default "1 1000 4000 10000"), 200 frames a route
#              (`sds demo --large --large-frames 200`: 1.7 GB of telemetry at 10,000 routes)
#   DENSE      also the 220 x 4,000-frame run (dense route XML, 442 waypoints a route): 1 (default)
set -euo pipefail
cd "$(dirname "$0")/.."
NEW=${1:?usage: bench/memory.sh NEW_SDS [OLD_SDS]}
OLD=${2:-}
OUT=${BENCH_DIR:-target/bench-memory}
ROUTES=${ROUTES:-1 1000 4000 10000}
mkdir -p "$OUT"
gen() { # dir routes frames
    [[ -f $1/.size && $(cat "$1/.size") == "$2 x $3" ]] && return
    "$NEW" demo "$1" --large --large-routes "$2" --large-frames "$3" --force >/dev/null 2>&1
    echo "$2 x $3" >"$1/.size"
}
rss() { # sds dir -> "peak_kb user_s sys_s"
    /usr/bin/time -f '%M %U %S' "$1" score --results "$2/results.json" --telemetry "$2/telemetry" \
        --routes "$2/routes.xml" -o "$2/report.json" --jobs 1 2>&1 >/dev/null | tail -n1
}
echo "| run | report JSON MB | new: peak RSS MB | old: peak RSS MB |"
echo "|---|---|---|---|"
runs=()
for n in $ROUTES; do gen "$OUT/r$n" "$n" 200; runs+=("$OUT/r$n"); done
[[ ${DENSE:-1} == 1 ]] && { gen "$OUT/dense220" 220 4000; runs+=("$OUT/dense220"); }
for d in "${runs[@]}"; do
    read -r nk _ _ < <(rss "$NEW" "$d")
    size=$(stat -c %s "$d/report.json")
    ok="-"
    if [[ -n $OLD ]]; then
        cp "$d/report.json" "$d/report.new.json"
        read -r ok _ _ < <(rss "$OLD" "$d")
        cmp -s "$d/report.json" "$d/report.new.json" || echo "warning: $d: reports differ" >&2
        ok=$(awk "BEGIN { printf \"%.1f\", $ok / 1024 }")
    fi
    echo "| $(cat "$d/.size") | $(awk "BEGIN { printf \"%.1f\", $size / 1048576 }") | $(awk "BEGIN { printf \"%.1f\", $nk / 1024 }") | $ok |"
done
