#!/usr/bin/env bash
# Short fuzz smoke run: each cargo-fuzz target of fuzz/ for FUZZ_SECONDS (default 20) seconds,
# starting from the committed corpus (fuzz/corpus/<target>, left unchanged: new inputs go to a
# temporary folder). Needs a nightly toolchain and cargo-fuzz; without them it prints a loud
# skip and exits 0. Exits non-zero if a target crashes (the input is kept in fuzz/artifacts/).
#
#   bash scripts/fuzz-smoke.sh                 # all eleven targets, 20 s each
#   FUZZ_SECONDS=600 FUZZ_SEED=0 bash scripts/fuzz-smoke.sh metric_info   # seed 0: a random one
# CI uses the fixed seed 1 so a run is repeatable; a crash found by a longer run goes into the corpus.
set -euo pipefail
cd "$(dirname "$0")/.."

TARGETS=("$@")
[ ${#TARGETS[@]} -gt 0 ] || TARGETS=(decode_frame metric_info results collision labels settings json_keys map table mcap merge_part)
SECONDS_EACH="${FUZZ_SECONDS:-20}"

skip() {
  echo "############################################################"
  echo "## fuzz smoke SKIPPED: $*"
  echo "## (install: rustup toolchain install nightly && cargo install cargo-fuzz)"
  echo "############################################################"
  if [ -n "${SDS_SKIP_LOG:-}" ]; then echo "fuzz smoke: $* (rustup toolchain install nightly && cargo install cargo-fuzz)" >>"$SDS_SKIP_LOG"; fi
  exit 0
}
command -v cargo >/dev/null 2>&1 || skip "cargo not found"
# Look nightly up in rustup's list: `cargo +nightly` alone could make rustup download one.
export RUSTUP_AUTO_INSTALL=0
rustup toolchain list 2>/dev/null | grep -q '^nightly' || skip "no nightly toolchain"
cargo +nightly fuzz --version >/dev/null 2>&1 || skip "cargo-fuzz is not installed"

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cd fuzz
status=0
failed=0
for t in "${TARGETS[@]}"; do
  echo "=== fuzz $t for ${SECONDS_EACH}s"
  mkdir -p "$work/$t"
  if cargo +nightly fuzz run -O "$t" "$work/$t" "corpus/$t" -- \
      -seed="${FUZZ_SEED:-1}" -max_total_time="$SECONDS_EACH" -rss_limit_mb=2048 -timeout=10 -print_final_stats=1 \
      >"$work/$t.log" 2>&1; then
    grep -E "^stat::number_of_executed_units|^Done " "$work/$t.log" | sed "s/^/    $t: /" || true
  else
    echo "!!! $t FAILED (crash, timeout or build error); last lines:"
    failed=$((failed + 1))
    tail -n 40 "$work/$t.log"
    status=1
  fi
done
echo "fuzz-smoke: $((${#TARGETS[@]} - failed)) passed, $failed failed"
exit "$status"
