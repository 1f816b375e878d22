#!/usr/bin/env bash
# Cross-check of our OpenDRIVE projection against CARLA's own map code (docs/MAPS.md): seeded
# points near every driving lane of the CARLA towns in ../shared/fixtures/maps (when present)
# and of the hand-made maps in monitor-host/tests/data/maps. Installs PyPI `carla==0.9.16` into a
# venv inside target/ (once); prints a loud SKIP and exits 0 when PyPI cannot be reached.
# Exits non-zero when a check fails.
#
#   bash scripts/map-crosscheck.sh                      # 100,000 points per town
#   MAP_CROSSCHECK_POINTS=10000 bash scripts/map-crosscheck.sh
set -euo pipefail
cd "$(dirname "$0")/.."

# Builds go to CARGO_TARGET_DIR when set (.ci/run shares one build folder with its clone run).
TARGET_DIR="${CARGO_TARGET_DIR:-target}"
WORK="$TARGET_DIR/map-crosscheck"
VENV="$WORK/venv"
POINTS="${MAP_CROSSCHECK_POINTS:-100000}"
OWN_POINTS="${MAP_CROSSCHECK_OWN_POINTS:-20000}"
TOWNS=../shared/fixtures/maps

skip() {
  echo "############################################################"
  echo "## map cross-check SKIPPED: $*"
  echo "############################################################"
  if [ -n "${SDS_SKIP_LOG:-}" ]; then echo "map cross-check: $*" >>"$SDS_SKIP_LOG"; fi
  exit 0
}

mkdir -p "$WORK"
if ! "$VENV/bin/python" -c 'import carla' >/dev/null 2>&1; then
  python3 -m venv "$VENV" || skip "python3 -m venv failed (install python3-venv)"
  if ! "$VENV/bin/pip" install --quiet --disable-pip-version-check 'carla==0.9.16' >"$WORK/pip.log" 2>&1; then
    if grep -qiE 'NewConnectionError|Network is unreachable|Temporary failure in name resolution|ConnectTimeout|Max retries exceeded|ProxyError|Connection refused' "$WORK/pip.log"; then
      skip "PyPI is unreachable (pip log: $WORK/pip.log)"
    fi
    echo "!!! pip could not install carla==0.9.16:" >&2
    tail -n 20 "$WORK/pip.log" >&2
    exit 1
  fi
fi

nice -n 10 cargo build --quiet --release -p monitor-host --example map_project
if [ -d "$TOWNS" ]; then
  towns=(--towns "$TOWNS")
else
  echo "!!! $TOWNS not found: CARLA towns skipped, hand-made maps only"
  towns=()
fi
"$VENV/bin/python" scripts/map_crosscheck.py --bin "$TARGET_DIR/release/examples/map_project" \
  --points "$POINTS" --own-points "$OWN_POINTS" "${towns[@]}" --own monitor-host/tests/data/maps
