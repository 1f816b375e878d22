#!/usr/bin/env bash
# The README's picture: the demo's collision without deceleration (the paper's Figure 2), as
# `sds score --traces` draws it, copied to docs/img/demo-collision-nodecel.svg.
#   bash scripts/readme-figure.sh          regenerate it
#   bash scripts/readme-figure.sh --check  fail when the committed file differs from what the
#                                          code draws (CI)
set -euo pipefail
cd "$(dirname "$0")/.."
target="${CARGO_TARGET_DIR:-target}"
figure=docs/img/demo-collision-nodecel.svg
cargo build -q --release -p sds-cli --bin sds
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$target/release/sds" demo "$tmp/demo" 2>/dev/null
"$target/release/sds" score --results "$tmp/demo/results.json" --telemetry "$tmp/demo/telemetry" \
  --routes "$tmp/demo/routes.xml" --traces "$tmp/traces" -o "$tmp/report.json" 2>/dev/null
drawn="$tmp/traces/RouteScenario_900005_rep0_collision0.svg"
[ -s "$drawn" ] || { echo "readme figure: the demo drew no $drawn" >&2; exit 1; }
if [ "${1:-}" = "--check" ]; then
  if ! cmp -s "$drawn" "$figure"; then
    echo "readme figure: $figure differs from what the code draws; run bash scripts/readme-figure.sh and commit it" >&2
    exit 1
  fi
  echo "readme figure: $figure matches the code"
else
  mkdir -p "$(dirname "$figure")"
  cp "$drawn" "$figure"
  echo "readme figure: wrote $figure"
fi
