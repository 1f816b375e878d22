#!/usr/bin/env bash
# Frames per second through the host checker (issue 49; docs/PERFORMANCE.md, "The live link").
# Not part of CI.
#   1. the checker alone: `sds checker` reading the doer's recorded bytes (sent.bin of a --tap)
#      from a file on standard input, answers to /dev/null: decode, E2E check, monitor, encode;
#   2. the round trip: `sds link --pace fast --to exec:'sds checker'`, the doer making the
#      frames from telemetry, encoding, writing them to the child, reading and decoding every
#      answer and replaying the accepted frames to compare (wall time of the whole command).
# Usage: bench/link.sh [SDS]   (default target/release/sds)
# Environment: BENCH_DIR (default target/bench-link; never committed), ROUTES (100), FRAMES (4000),
#   REPEAT (3: the best of REPEAT runs is reported).
set -euo pipefail
cd "$(dirname "$0")/.."
SDS=$(realpath "${1:-target/release/sds}")
OUT=${BENCH_DIR:-target/bench-link}
ROUTES=${ROUTES:-100}
FRAMES=${FRAMES:-4000}
REPEAT=${REPEAT:-3}
mkdir -p "$OUT"
RUN="$OUT/run-$ROUTES-$FRAMES"
if [[ ! -f $RUN/results.json ]]; then
    "$SDS" demo "$RUN" --large --large-routes "$ROUTES" --large-frames "$FRAMES" --force >/dev/null 2>&1
fi
best() { sort -g | head -n1; }
# Wall seconds of a command (its output discarded).
wall() {
    local t0=$EPOCHREALTIME
    "$@" >/dev/null 2>&1
    python3 -c "import sys; print(f'{float(sys.argv[2]) - float(sys.argv[1]):.3f}')" "$t0" "$EPOCHREALTIME"
}
trip=$(for _ in $(seq "$REPEAT"); do
    wall "$SDS" link --results "$RUN/results.json" --telemetry "$RUN/telemetry" \
        --routes "$RUN/routes.xml" --to "exec:$SDS checker" --tap "$OUT/tap" -o "$OUT/link.json"
done | best)
frames=$(python3 -c 'import json,sys; r=json.load(open(sys.argv[1])); print(sum(v for x in r["routes"] for k, v in x["link"]["statuses"].items() if k != "NONEWDATA"))' "$OUT/link.json")
equal=$(python3 -c 'import json,sys; s=json.load(open(sys.argv[1]))["summary"]; print(s["equal_routes"], s["routes"], sep="/")' "$OUT/link.json")
bytes=$(stat -c %s "$OUT/tap/sent.bin")
alone=$(for _ in $(seq "$REPEAT"); do
    wall sh -c '"$1" checker <"$2"' sh "$SDS" "$OUT/tap/sent.bin"
done | best)
fps() { python3 -c "import sys; t=float(sys.argv[2]); print(f'{int(sys.argv[1])/t:,.0f}' if t > 0 else 'n/a')" "$1" "$2"; }
echo "run: $ROUTES routes x $FRAMES frames ($frames frame messages, $bytes bytes on the wire), $(nproc) cores, best of $REPEAT"
echo "| path | wall s | frames/s |"
echo "|---|---|---|"
echo "| checker alone (\`sds checker < sent.bin\`) | $alone | $(fps "$frames" "$alone") |"
echo "| round trip (\`sds link --to exec:'sds checker'\`, equal $equal) | $trip | $(fps "$frames" "$trip") |"
