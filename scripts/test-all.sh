#!/usr/bin/env bash
# Every test of the project: formatting, lints, unit/property/end-to-end tests, docs, the
# no_std build of the core, and the firmware under QEMU. This is the README's test command and
# what CI runs.
#
#   bash scripts/test-all.sh             every step, in order
#   bash scripts/test-all.sh --list      the steps' names, one a line, with what each checks
#   bash scripts/test-all.sh STEP...     only these steps, in the order given
#
# Every selected step runs even when an earlier one failed; the failures (and their times) are
# listed at the end and the script then exits 1.
set -euo pipefail
cd "$(dirname "$0")/.."

# name|title, in the order `test-all.sh` runs them. Each step is the function step_<name> (a `-`
# in the name is `_` in the function).
STEPS=(
  "setup|setup"
  "setup-test|setup works from nothing (sandbox PATH, stub package managers; installs nothing)"
  "fmt|cargo fmt --check"
  "module-graph|module graph: no import cycle in monitor-host/src, no upward import, none through the crate root"
  "cite-docs|citations: every §N names a document and section this checkout holds"
  "clippy|cargo clippy"
  "clippy-lib|library and core without default features"
  "test|cargo test"
  "test-debug|cargo test, debug profile (overflow checks on): monitor-core, monitor-host, sds-cli (the doc examples ran in test)"
  "html|HTML report: parsed against the JSON report, then in headless Chromium (sort, filter, screenshot)"
  "readme-figure|the README's figure matches what the code draws"
  "doc|cargo doc (warnings denied)"
  "nostd|monitor-core for Cortex-M (no std, no alloc)"
  "python|Python package (wheel, pytest, mypy --strict)"
  "firmware|firmware under QEMU"
  "capi|C API: C/C++ tests, valgrind, Cortex-M4F C firmware under QEMU"
  "map-crosscheck|map cross-check against CARLA's map code (skips without PyPI)"
  "fuzz|fuzz smoke (each target briefly, from the committed corpus)"
)

step_setup() { bash scripts/setup.sh; }
step_setup_test() { bash scripts/setup-test.sh; }
step_fmt() { cargo fmt --all --check; }
step_module_graph() { python3 scripts/module-graph.py --check; }
step_cite_docs() { python3 scripts/cite-docs.py --check; }
step_clippy() { cargo clippy --workspace --all-targets -- -D warnings; }
step_clippy_lib() {
  cargo clippy -p monitor-host --no-default-features --all-targets -- -D warnings
  cargo clippy -p monitor-core --no-default-features -- -D warnings
}
step_test() {
  [ -d ../shared/fixtures ] || echo "note: ../shared/fixtures is absent: the tests on real Bench2Drive files skip (each says why under --nocapture)"
  cargo test --workspace --release
}
# The doc examples are left to `test`: compiling each again unoptimised took a minute a run.
step_test_debug() { cargo test -p monitor-core -p monitor-host -p sds-cli --lib --bins --tests; }
step_html() { bash scripts/html-report-test.sh; }
step_readme_figure() { bash scripts/readme-figure.sh --check; }
step_doc() { RUSTDOCFLAGS="-D warnings" cargo doc --workspace --no-deps --quiet; }
step_nostd() { bash scripts/core-nostd.sh; }
step_python() { bash bindings/python/run-tests.sh; }
step_firmware() {
  if [ -x firmware-example/run-tests.sh ]; then
    bash firmware-example/run-tests.sh
  else
    echo "no firmware-example/run-tests.sh: nothing to run"
  fi
}
step_capi() { bash bindings/c/run-tests.sh; }
step_map_crosscheck() { bash scripts/map-crosscheck.sh; }
step_fuzz() { FUZZ_SECONDS="${FUZZ_SECONDS:-10}" bash scripts/fuzz-smoke.sh; }

names=()
for s in "${STEPS[@]}"; do names+=("${s%%|*}"); done

if [ "${1:-}" = "--list" ]; then
  for s in "${STEPS[@]}"; do printf '%-15s %s\n' "${s%%|*}" "${s#*|}"; done
  exit 0
fi
selected=("$@")
[ ${#selected[@]} -gt 0 ] || selected=("${names[@]}")
for want in "${selected[@]}"; do
  found=no
  for n in "${names[@]}"; do [ "$n" = "$want" ] && found=yes; done
  if [ $found = no ]; then
    echo "test-all.sh: no step named '$want'; the steps (--list): ${names[*]}" >&2
    exit 2
  fi
done

# Every skipped check is recorded here and listed at the end (scripts/skip.sh).
export SDS_SKIP_LOG="${CARGO_TARGET_DIR:-$(pwd)/target}/test-all-skipped.txt"
mkdir -p "$(dirname "$SDS_SKIP_LOG")" && : >"$SDS_SKIP_LOG"

# One build cache may serve checkouts at different paths (.ci/run's clone shares it). Cargo keeps
# a crate's build while the crate's files are older than it, even when it was built from another
# checkout, and a test keeps the checkout path it was built from (CARGO_MANIFEST_DIR: its golden
# files, ../shared): the project's own crates are rebuilt when the cache was last built elsewhere.
# Run once, after the setup steps (which install the toolchain) and before the first other step.
cache_checked=no
check_cache() {
  [ $cache_checked = no ] || return 0
  cache_checked=yes
  local target_dir="${CARGO_TARGET_DIR:-$(pwd)/target}"
  local built_from="$target_dir/.built-from"
  if [ "$(cat "$built_from" 2>/dev/null)" != "$(pwd)" ]; then
    echo "note: the build cache was last built from $(cat "$built_from" 2>/dev/null || echo "an unknown folder"): rebuilding this checkout's crates"
    for profile in "" --release; do
      cargo clean -q $profile -p monitor-core -p monitor-host -p sds-cli -p sds-tests -p sds-capi -p sds-python
    done
  fi
  mkdir -p "$target_dir" && pwd >"$built_from"
}

last_step="(start)"
timings=()
failures=()
run_start=$SECONDS
for want in "${selected[@]}"; do
  # No step may turn a device node into a file (a rename onto /dev/null as root once did).
  [ -c /dev/null ] || { echo "FAILED: /dev/null is no longer a character device after: $last_step" >&2; exit 1; }
  for s in "${STEPS[@]}"; do
    if [ "${s%%|*}" = "$want" ]; then
      last_step="$want: ${s#*|}"
      printf '\n=== %s\n' "$last_step"
    fi
  done
  case "$want" in setup | setup-test) ;; *) check_cache ;; esac
  step_start=$SECONDS
  # In a subshell with its own `set -e`: a failing step stops itself, not the run (a failing
  # python step once hid firmware, capi, map-crosscheck and fuzz); every failure is listed at
  # the end. (`if step; then` would turn `set -e` off inside the step.)
  set +e
  (set -e; "step_${want//-/_}")
  rc=$?
  set -e
  took=$((SECONDS - step_start))
  if [ $rc -eq 0 ]; then
    timings+=("$(printf '%-15s %4d s' "$want" $took)")
  else
    timings+=("$(printf '%-15s %4d s  FAILED (exit %d)' "$want" $took $rc)")
    failures+=("$(printf '%-15s exit %d after %d s: %s' "$want" $rc $took "$last_step")")
    printf '\n=== FAILED: %s (exit %d after %d s); going on with the next step\n' "$want" $rc $took >&2
  fi
done
[ -c /dev/null ] || { echo "FAILED: /dev/null is no longer a character device after: $last_step" >&2; exit 1; }

printf '\n=== %s\n' "end"
# Where the run's time went, so a slow step shows (CI's budget is 40 minutes for both runs).
echo "time per step ($((SECONDS - run_start)) s in all):"
printf '  %s\n' "${timings[@]}"
if [ -s "$SDS_SKIP_LOG" ]; then
  echo "SKIPPED checks ($(wc -l <"$SDS_SKIP_LOG")):"
  sed 's/^/  - /' "$SDS_SKIP_LOG"
else
  echo "nothing was skipped"
fi
echo
if [ ${#failures[@]} -gt 0 ]; then
  echo "FAILED steps (${#failures[@]} of ${#selected[@]}; every other step ran):"
  printf '  - %s\n' "${failures[@]}"
  exit 1
fi
if [ $# -gt 0 ]; then
  echo "steps passed: ${selected[*]}"
else
  echo "all checks passed"
fi
