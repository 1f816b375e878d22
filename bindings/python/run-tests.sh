#!/usr/bin/env bash
# The Python package's tests: build the abi3 wheel with maturin, install it into a fresh venv
# inside the build folder, run pytest (the package against the `sds` binary) and
# `mypy --strict` on the package, its stubs and the examples. Then the install from source:
# `maturin sdist`, `pip install` of the .tar.gz into another fresh venv (pip builds it with
# maturin and cargo), its `sds` command and `import sds`, and pytest again on that install.
# The tools come from scripts/setup.sh (pinned, in $CARGO_TARGET_DIR/py-tools; the wheelhouse
# holds maturin too, so both installs work offline); without them this skips, loudly.
set -euo pipefail
cd "$(dirname "$0")"
root=$(cd ../.. && pwd)
target="${CARGO_TARGET_DIR:-$root/target}"
tools="$target/py-tools"
if [ ! -x "$tools/bin/maturin" ] || [ ! -f "$tools/pins" ]; then
  source "$root/scripts/skip.sh"
  loud_skip python "Python package tests: $tools has no maturin (run scripts/setup.sh; is PyPI reachable?)"
fi

echo "[python] building the sds binary (the reference the tests compare with) and the wheel"
cargo build -q --release -p sds-cli --bin sds
rm -rf "$target/py-wheels"
"$tools/bin/maturin" build -q --release -o "$target/py-wheels"
wheel=$(ls "$target"/py-wheels/sds_monitor-*-abi3-*.whl)

venv="$target/py-test"
echo "[python] fresh venv $venv: $(basename "$wheel") and the test requirements (offline)"
python3 -m venv --clear "$venv"
"$venv/bin/pip" install -q --no-index --find-links "$tools/wheelhouse" "$wheel" pytest mypy numpy pandas
# The data packages (Parquet, DuckDB, trackers), offline, where setup could download them; the
# tests that need one skip with the reason (pytest -rs prints it).
if [ -f "$tools/data-pins" ]; then
  # shellcheck disable=SC2046
  "$venv/bin/pip" install -q --no-index --find-links "$tools/wheelhouse" $(cat "$tools/data-pins") \
    || echo "[python] SKIP: the data packages ($(cat "$tools/data-pins")) did not install; their tests skip" >&2
else
  echo "[python] SKIP: no data packages in $tools (rerun scripts/setup.sh; is PyPI reachable?): the Parquet, DuckDB and tracker tests skip" >&2
fi
# Ray for the scale-out tests (pinned apart in scripts/setup.sh), and the MCAP writer's packages
# (mcap, mcap-ros2-support: pinned in scripts/setup.sh) for the fleet test's logs; without them
# those tests skip, naming why. Offline from the wheelhouse, measured on 2 busy cores: ray 46 s
# (a 79 MB wheel), the writer's packages 11 s (with lz4 and zstandard).
"$venv/bin/pip" install -q --no-index --find-links "$tools/wheelhouse" ray 2>/dev/null \
  || echo "[python] ray is not in $tools/wheelhouse (scripts/setup.sh could not download it): the Ray tests skip"
"$venv/bin/pip" install -q --no-index --find-links "$tools/wheelhouse" mcap mcap-ros2-support 2>/dev/null \
  || echo "[python] mcap-ros2-support is not in $tools/wheelhouse (rerun scripts/setup.sh): the fleet test skips"

echo "[python] mypy --strict: package, stubs, examples"
MYPYPATH=python "$venv/bin/python" -m mypy --strict --cache-dir "$target/py-mypy-cache" python/sds examples

echo "[python] pytest"
(cd tests && SDS_BIN="$target/release/sds" "$venv/bin/python" -m pytest -q -rs -p no:cacheprovider .)

# Install from source, as `pip install sds_monitor-X.tar.gz` does on a machine without our wheel.
if ! ls "$tools"/wheelhouse/maturin-*.whl >/dev/null 2>&1; then
  source "$root/scripts/skip.sh"
  loud_skip python "install from the source distribution: no maturin in $tools/wheelhouse to build it offline (rerun scripts/setup.sh; is PyPI reachable?)"
fi
rm -rf "$target/py-sdist"
"$tools/bin/maturin" sdist -o "$target/py-sdist" >"$target/py-sdist.log" 2>&1 \
  || { cat "$target/py-sdist.log" >&2; echo "FAILED: maturin sdist" >&2; exit 1; }
sdist=$(ls "$target"/py-sdist/sds_monitor-*.tar.gz)
venv="$target/py-test-sdist"
echo "[python] fresh venv $venv: pip install $(basename "$sdist") (built from source, offline)"
python3 -m venv --clear "$venv"
# pip builds the wheel in an isolated environment (maturin from the wheelhouse) with cargo: no
# wheel cache, and a target folder of its own in which the project's crates are always built
# afresh: the sdist's files carry fixed times, so cargo took a previous run's artifacts of them for
# fresh and installed a stale build (measured). Its registry crates are kept from run to run
# (.ci/run's second run, a rerun here): they are the same crates, and compiling them again took
# two minutes a run.
cargo clean -q --release --target-dir "$target/py-sdist-build" \
  -p sds-python -p sds-cli -p monitor-host -p monitor-core
CARGO_TARGET_DIR="$target/py-sdist-build" "$venv/bin/pip" install -q --no-cache-dir --no-index \
  --find-links "$tools/wheelhouse" "$sdist" pytest numpy pandas
installed=$("$venv/bin/sds" --version)
[ "$installed" = "$("$target/release/sds" --version)" ] \
  || { echo "FAILED: the sds command installed from source says '$installed'" >&2; exit 1; }
"$venv/bin/python" -c 'import sds, sys; assert sds.__version__ == sys.argv[1].split()[1], sds.__version__; assert issubclass(sds.NeedsLabelsError, sds.SdsError)' "$installed"
echo "[python] installed from source: $installed; import sds ok; pytest on that install"
(cd tests && SDS_BIN="$target/release/sds" "$venv/bin/python" -m pytest -q -rs -p no:cacheprovider .)
