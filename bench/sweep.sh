#!/usr/bin/env bash
# Benchmark of `sds compare --sweep` (issue 50, docs/PERFORMANCE.md "The sweep"): a 3 x 3 sweep of
# four 220-route models with telemetry against one `sds compare` of them. Not a test: it prints
# the times and their ratio against the goal (under 10x). Takes a few minutes on 2 cores and
# writes about 3 GB of generated runs (never committed).
#
# Usage: bench/sweep.sh
# Environment:
#   CARGO_TARGET_DIR  cargo's target dir (default: target/ in the repository)
#   BENCH_DIR         where the runs go (default: $CARGO_TARGET_DIR/bench-sweep)
#   ROUTES, FRAMES    size of each model's run (default 220 x 4000, as bench/run.sh's large run)
#   REPS              runs of each measurement; the smallest CPU and wall time are kept (default 3)
set -euo pipefail

cd "$(dirname "$0")/.."
ROOT=$(pwd)
TARGET=${CARGO_TARGET_DIR:-$ROOT/target}
export CARGO_TARGET_DIR=$TARGET
OUT=${BENCH_DIR:-$TARGET/bench-sweep}
ROUTES=${ROUTES:-220}
FRAMES=${FRAMES:-4000}
REPS=${REPS:-3}
mkdir -p "$OUT"
say() { echo "bench: $*" >&2; }

say "building (release)"
cargo build --release -p sds-cli --bin sds >/dev/null 2>&1
SDS=$TARGET/release/sds

# Four models: the demo writer's large run with 0, 20, 40 and 60 colliding routes (as
# bench/run.sh generates its runs), so the models' figures differ.
RUNS=()
for k in 0 1 2 3; do
    dir=$OUT/m$k
    size="$ROUTES x $FRAMES collisions $((20 * k))"
    if ! [[ -f $dir/.size && $(cat "$dir/.size") == "$size" && $dir/.size -nt $SDS ]]; then
        say "writing model m$k ($size)"
        rm -rf "$dir"
        "$SDS" demo "$dir" --large --large-routes "$ROUTES" --large-frames "$FRAMES" \
            --large-collisions $((20 * k)) >/dev/null
        echo "$size" >"$dir/.size"
    fi
    RUNS+=("m$k=$dir/results.json:$dir/telemetry")
done
ROUTES_XML=$OUT/m0/routes.xml
# Warm the page cache: every measurement reads the same files from memory.
find "$OUT" -name metric_info.json -exec cat {} + >/dev/null

# measure ARGS... -> "wall cpu": the smallest of REPS runs of `sds compare ARGS`.
measure() {
    local w="" c="" line
    for _ in $(seq "$REPS"); do
        /usr/bin/time -o "$OUT/time.txt" -f '%e %U %S' "$SDS" compare "${RUNS[@]}" \
            --routes "$ROUTES_XML" --format json -o "$OUT/compare.json" "$@" >/dev/null 2>&1
        line=$(tail -n1 "$OUT/time.txt")
        read -r lw lu ls <<<"$line"
        local lc
        lc=$(awk "BEGIN { print $lu + $ls }")
        if [[ -z $w ]] || awk "BEGIN { exit !($lw < $w) }"; then w=$lw; fi
        if [[ -z $c ]] || awk "BEGIN { exit !($lc < $c) }"; then c=$lc; fi
    done
    echo "$w $c"
}

say "one sds compare of the four models"
read -r base_w base_c <<<"$(measure)"
printf '%-64s %8s %8s %8s\n' "measurement" "wall s" "CPU s" "x CPU"
printf '%-64s %8.2f %8.2f %8s\n' "sds compare (4 models x $ROUTES routes x $FRAMES frames)" "$base_w" "$base_c" "1.0"
row() { # label sweep-args...
    local label=$1
    shift
    say "$label"
    read -r w c <<<"$(measure "$@")"
    local ratio
    ratio=$(awk "BEGIN { printf \"%.1f\", $c / $base_c }")
    local status
    status=$(awk "BEGIN { print ($c / $base_c < 10) ? \"ok\" : \"over\" }")
    printf '%-64s %8.2f %8.2f %8s  (goal < 10x: %s)\n' "$label" "$w" "$c" "$ratio" "$status"
}
row "3x3: critical_excess x factors.critical (monitor x penalty)" \
    --sweep critical_excess=0.45,0.65,0.85 --sweep factors.critical=0.8,0.9,1
row "3x3: critical_excess x bounds.lat_acc (monitor x monitor)" \
    --sweep critical_excess=0.45,0.65,0.85 --sweep bounds.lat_acc=3,4.89,6
row "3x3: chunk_len x critical_excess (replay x monitor)" \
    --sweep chunk_len=10,15,20 --sweep critical_excess=0.45,0.65,0.85
