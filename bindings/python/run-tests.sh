#!/usr/bin/env bash
# The Python package's tests: build the abi3 wheel with maturin, install it into a fresh venv
# inside the build folder, run pytest (the package against the `sds` binary) and
# `mypy --strict` on the package, its stubs and the examples. The tools come from
# scripts/setup.sh (pinned, in $CARGO_TARGET_DIR/py-tools); without them this skips, loudly.
set -euo pipefail
cd "$(dirname "$0")"
root=$(cd ../.. && pwd)
target="${CARGO_TARGET_DIR:-$root/target}"
tools="$target/py-tools"
if [ ! -x "$tools/bin/maturin" ] || [ ! -f "$tools/pins" ]; then
  echo "SKIPPED: Python package tests: $tools has no maturin (run scripts/setup.sh; is PyPI reachable?)" >&2
  exit 0
fi

echo "[python] building the sds binary (the reference the tests compare with) and the wheel"
cargo build -q --release -p monitor-host --bin sds
rm -rf "$target/py-wheels"
"$tools/bin/maturin" build -q --release -o "$target/py-wheels"
wheel=$(ls "$target"/py-wheels/sds_monitor-*-abi3-*.whl)

venv="$target/py-test"
echo "[python] fresh venv $venv: $(basename "$wheel") and the test requirements (offline)"
python3 -m venv --clear "$venv"
"$venv/bin/pip" install -q --no-index --find-links "$tools/wheelhouse" "$wheel" pytest mypy numpy

echo "[python] mypy --strict: package, stubs, examples"
MYPYPATH=python "$venv/bin/python" -m mypy --strict --cache-dir "$target/py-mypy-cache" python/sds examples

echo "[python] pytest"
cd tests
SDS_BIN="$target/release/sds" "$venv/bin/python" -m pytest -q -p no:cacheprovider .
