#!/usr/bin/env bash
# Peak RSS of `sds score --mcap --jobs 1` against a drive's length (issue 51 goal 2), side by side
# with another binary (main's, built into a separate target dir first). Not part of CI.
#
# Usage: bench/drive-memory.sh NEW_SDS [OLD_SDS]
# Environment:
#   BENCH_DIR  where the logs go (default: target/bench-drive); never committed
#   SECONDS_LIST  drive lengths in seconds (default "600 3600 28800": 10 min, 1 h, 8 h at 20 Hz;
#              the 8-h log is ~0.2 GB, written by monitor-host's `write_drive` example)
set -euo pipefail
cd "$(dirname "$0")/.."
NEW=${1:?usage: bench/drive-memory.sh NEW_SDS [OLD_SDS]}
OLD=${2:-}
OUT=${BENCH_DIR:-target/bench-drive}
LENGTHS=${SECONDS_LIST:-600 3600 28800}
mkdir -p "$OUT"
cargo build --release -q -p monitor-host --example write_drive
WRITER=${CARGO_TARGET_DIR:-target}/release/examples/write_drive
rss() { # sds log report -> "peak_kb user_s sys_s"
    /usr/bin/time -f '%M %U %S' "$1" score --mcap "$2" --topic event=/events -o "$3" --jobs 1 \
        2>&1 >/dev/null | tail -n1
}
echo "| drive | frames | log MB | new: peak RSS MB | new: CPU s | old: peak RSS MB | old: CPU s |"
echo "|---|---|---|---|---|---|---|"
for s in $LENGTHS; do
    log="$OUT/drive$s.mcap"
    [[ -f $log ]] || "$WRITER" "$log" "$s"
    read -r nk nu ns < <(rss "$NEW" "$log" "$OUT/report$s.new.json")
    ok="-" ocpu="-"
    if [[ -n $OLD ]]; then
        read -r ok ou os < <(rss "$OLD" "$log" "$OUT/report$s.old.json")
        cmp -s "$OUT/report$s.new.json" "$OUT/report$s.old.json" || echo "warning: $log: reports differ" >&2
        ok=$(awk "BEGIN { printf \"%.1f\", $ok / 1024 }")
        ocpu=$(awk "BEGIN { printf \"%.2f\", $ou + $os }")
    fi
    frames=$(grep -o '"frames": *[0-9]*' "$OUT/report$s.new.json" | head -n1 | grep -o '[0-9]*$' || echo "?")
    echo "| $((s / 60)) min | $frames | $(awk "BEGIN { printf \"%.1f\", $(stat -c %s "$log") / 1e6 }") | $(awk "BEGIN { printf \"%.1f\", $nk / 1024 }") | $(awk "BEGIN { printf \"%.2f\", $nu + $ns }") | $ok | $ocpu |"
done
