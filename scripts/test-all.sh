#!/usr/bin/env bash
# Every test of the project: formatting, lints, unit/property/end-to-end tests, docs, the
# no_std build of the core, and the firmware under QEMU. This is the README's test command and
# what CI runs.
set -euo pipefail
cd "$(dirname "$0")/.."

# Every skipped check is recorded here and listed at the end (scripts/skip.sh).
export SDS_SKIP_LOG="${CARGO_TARGET_DIR:-$(pwd)/target}/test-all-skipped.txt"
mkdir -p "$(dirname "$SDS_SKIP_LOG")" && : >"$SDS_SKIP_LOG"

last_step="(start)"
step() {
  # No step may turn a device node into a file (a rename onto /dev/null as root once did).
  [ -c /dev/null ] || { echo "FAILED: /dev/null is no longer a character device after: $last_step" >&2; exit 1; }
  last_step="$*"
  printf '\n=== %s\n' "$*"
}

step "setup"
bash scripts/setup.sh

# One build cache may serve checkouts at different paths (.ci/run's clone shares it). Cargo keeps
# a crate's build while the crate's files are older than it, even when it was built from another
# checkout, and a test keeps the checkout path it was built from (CARGO_MANIFEST_DIR: its golden
# files, ../shared): the project's own crates are rebuilt when the cache was last built elsewhere.
target_dir="${CARGO_TARGET_DIR:-$(pwd)/target}"
built_from="$target_dir/.built-from"
if [ "$(cat "$built_from" 2>/dev/null)" != "$(pwd)" ]; then
  echo "note: the build cache was last built from $(cat "$built_from" 2>/dev/null || echo "an unknown folder"): rebuilding this checkout's crates"
  for profile in "" --release; do
    cargo clean -q $profile -p monitor-core -p monitor-host -p sds-tests -p sds-capi -p sds-python
  done
fi
mkdir -p "$target_dir" && pwd >"$built_from"

step "setup works from nothing (sandbox PATH, stub package managers; installs nothing)"
bash scripts/setup-test.sh

step "cargo fmt --check"
cargo fmt --all --check

step "cargo clippy"
cargo clippy --workspace --all-targets -- -D warnings

step "library builds without the command line (what the bindings compile)"
cargo clippy -p monitor-host --no-default-features --all-targets -- -D warnings
cargo clippy -p monitor-core --no-default-features -- -D warnings

step "cargo test"
[ -d ../shared/fixtures ] || echo "note: ../shared/fixtures is absent: the tests on real Bench2Drive files skip (each says why under --nocapture)"
cargo test --workspace --release

step "cargo test, debug profile (overflow checks on): monitor-core and monitor-host"
cargo test -p monitor-core -p monitor-host

step "HTML report: parsed against the JSON report, then in headless Chromium (sort, filter, screenshot)"
bash scripts/html-report-test.sh

step "the README's figure matches what the code draws"
bash scripts/readme-figure.sh --check

step "cargo doc (warnings denied)"
RUSTDOCFLAGS="-D warnings" cargo doc --workspace --no-deps --quiet

step "monitor-core for Cortex-M (no std, no alloc)"
bash scripts/core-nostd.sh

step "Python package (wheel, pytest, mypy --strict)"
bash bindings/python/run-tests.sh

if [ -x firmware-example/run-tests.sh ]; then
  step "firmware under QEMU"
  bash firmware-example/run-tests.sh
fi
step "C API: C/C++ tests, valgrind, Cortex-M4F C firmware under QEMU" && bash bindings/c/run-tests.sh
step "map cross-check against CARLA's map code (skips without PyPI)"
bash scripts/map-crosscheck.sh

step "fuzz smoke (each target briefly, from the committed corpus)"
FUZZ_SECONDS="${FUZZ_SECONDS:-10}" bash scripts/fuzz-smoke.sh

step "end"
if [ -s "$SDS_SKIP_LOG" ]; then
  echo "SKIPPED checks ($(wc -l <"$SDS_SKIP_LOG")): everything else passed"
  sed 's/^/  - /' "$SDS_SKIP_LOG"
else
  echo "nothing was skipped"
fi
echo
echo "all checks passed"
