#!/usr/bin/env bash
# The HTML report's size and load time (docs/PERFORMANCE.md): a run of 220 routes x 4,000 frames
# where 100 routes collide, scored to HTML, then opened in headless Chromium RUNS times. Prints
# the file size, the time at which the page's script finished its checks (performance.now(),
# from navigation start: parse, style, the script), and the wall time of a screenshot of the
# page against a screenshot of about:blank (browser start-up), medians over the runs.
set -euo pipefail
cd "$(dirname "$0")/.."
target="${CARGO_TARGET_DIR:-target}"
runs="${RUNS:-5}"
out="$target/html-bench"
chrome=$(command -v chromium || command -v chromium-browser) || { echo "needs chromium (scripts/setup.sh)" >&2; exit 1; }
cargo build -q --release -p sds-cli --bin sds
sds="$target/release/sds"
if [ ! -s "$out/run/results.json" ]; then
  rm -rf "$out"; "$sds" demo "$out/run" --large --large-collisions 100 2>/dev/null
fi
"$sds" score --results "$out/run/results.json" --telemetry "$out/run/telemetry" \
  --routes "$out/run/routes.xml" --format html -o "$out/report.html" 2>/dev/null
bytes=$(stat -c %s "$out/report.html")
shot() { # shot URL -> wall seconds of a 1280x2000 screenshot
  local p; p=$(mktemp -d)
  local t0; t0=$(date +%s.%N)
  timeout 120 "$chrome" --headless --no-sandbox --disable-gpu --disable-background-networking \
    --disable-component-update --no-first-run --user-data-dir="$p" --window-size=1280,2000 \
    --screenshot="$p/s.png" "$1" >/dev/null 2>&1
  echo "$(date +%s.%N) - $t0" | bc; rm -rf "$p"
}
checked=(); page=(); blank=()
for _ in $(seq "$runs"); do
  p=$(mktemp -d)
  ms=$(timeout 120 "$chrome" --headless --no-sandbox --disable-gpu --disable-background-networking \
    --disable-component-update --no-first-run --user-data-dir="$p" --dump-dom \
    "file://$(realpath "$out/report.html")" 2>/dev/null | sed -n 's/.*checked \([0-9]*\) ms.*/\1/p')
  rm -rf "$p"; checked+=("$ms")
  page+=("$(shot "file://$(realpath "$out/report.html")")")
  blank+=("$(shot about:blank)")
done
median() { printf '%s\n' "$@" | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
echo "report: $out/report.html, $bytes bytes ($(echo "scale=2; $bytes/1048576" | bc) MiB)"
echo "script checks done (median of $runs): $(median "${checked[@]}") ms after navigation start"
echo "screenshot wall, page (median): $(median "${page[@]}") s; about:blank: $(median "${blank[@]}") s"
