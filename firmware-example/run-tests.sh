#!/usr/bin/env bash
# The firmware's tests: builds the Cortex-M monitor for Cortex-M4F (mps2-an386) and Cortex-M3
# (lm3s6965evb), runs it under QEMU and checks, with every route of `sds demo` in flash:
#   1. host == firmware: event, summary and pin lines byte-identical to `monitor_replay`'s;
#   2. no panicking branch survives in the monitor path (release build links with a panic
#      handler that cannot link), and the check itself can fail (a planted panic must not link);
#   3. flash and RAM sizes, and the monitor's state size, within budgets.sh;
#   4. instructions per frame (average and worst frame), counted by QEMU with -icount shift=0
#      and our insncount plugin (qemu-plugin/insncount.c, built here), within budgets.sh;
#   5. stack high-water mark (cortex-m-rt paint-stack) within budgets.sh;
#   6. the link checker image (link-checker/, Cortex-M4F): `sds link` plays the demo run into it
#      over a TCP character device, without and with faults, every route equal to the replay;
#      its sizes, stack and instructions per message within budgets.sh (link-checker/run-link.sh).
# Idempotent; everything it writes goes to firmware-example/target/ (git-ignored; builds go to
# $CARGO_TARGET_DIR/firmware-example instead when CARGO_TARGET_DIR is set). Measurements
# are summarised in target/qemu-tests/measurements.txt (docs/FIRMWARE.md records them).
#
# Environment: QEMU_TIMEOUT (seconds per QEMU run, default 60); FIRMWARE_FRAMES=FILE.jsonl to
# test a frames file of your own instead of the demo routes (development only).
set -euo pipefail

FW="$(cd "$(dirname "$0")" && pwd)"
ROOT="$(cd "$FW/.." && pwd)"
OUT="$FW/target/qemu-tests"
# The firmware's own build directory: firmware-example/target, or a subfolder of CARGO_TARGET_DIR
# when one is set (CI shares one build cache between its runs).
FW_TARGET="${CARGO_TARGET_DIR:+$CARGO_TARGET_DIR/firmware-example}"
FW_TARGET="${FW_TARGET:-$FW/target}"
QEMU_TIMEOUT="${QEMU_TIMEOUT:-60}"
# shellcheck source=budgets.sh
source "$FW/budgets.sh"

say() { printf '[firmware] %s\n' "$*"; }
fail() {
  printf '[firmware] FAILED: %s\n' "$*" >&2
  exit 1
}
# shellcheck source=../scripts/skip.sh
source "$ROOT/scripts/skip.sh"

rm -rf "$OUT"
mkdir -p "$OUT"

# --- tools -------------------------------------------------------------------------------------
TARGETS=(thumbv7em-none-eabihf thumbv7m-none-eabi)
BUILD_STD=()
have_target() {
  [ -d "$(rustc --print sysroot)/lib/rustlib/$1/lib" ]
}
missing=()
for t in "${TARGETS[@]}"; do
  if ! have_target "$t" && command -v rustup >/dev/null 2>&1; then
    say "adding rust target $t"
    rustup target add "$t" >/dev/null 2>&1 || true
  fi
  have_target "$t" || missing+=("$t")
done
if [ ${#missing[@]} -gt 0 ]; then
  # Fallback: build core from source (Debian's rustc-web/cargo-web ship rust-src).
  if [ -d "$(rustc --print sysroot)/lib/rustlib/src/rust/library/core" ]; then
    say "targets ${missing[*]} unavailable: building core from source (-Z build-std)"
    export RUSTC_BOOTSTRAP=1
    BUILD_STD=(-Z build-std=core)
  else
    loud_skip firmware "no thumb target (${missing[*]}): neither rustup targets nor rust-src for -Z build-std; the firmware was NOT tested"
  fi
fi
need_tools firmware qemu-system-arm=qemu-system-arm arm-none-eabi-size=binutils-arm-none-eabi \
  arm-none-eabi-nm=binutils-arm-none-eabi arm-none-eabi-objdump=binutils-arm-none-eabi \
  arm-none-eabi-addr2line=binutils-arm-none-eabi gcc=gcc timeout=coreutils
say "$(qemu-system-arm --version | head -1)"

# The instruction counter: our TCG plugin (qemu-plugin/), API version 2, which QEMU 9.0 and later
# accept; an older QEMU refuses to load it, so say so up front.
PLUGIN="$OUT/libinsncount.so"
qemu_major=$(qemu-system-arm --version | sed -n '1s/.*version \([0-9]*\)\..*/\1/p')
[ "${qemu_major:-0}" -ge 9 ] || fail "qemu-system-arm ${qemu_major:-?}.x is too old for the insncount plugin (API 2 needs QEMU >= 9.0; bash scripts/setup.sh installs it from bookworm-backports)"
gcc -shared -fPIC -O2 -Wall -Wextra -Werror -fvisibility=hidden -o "$PLUGIN" "$FW/qemu-plugin/insncount.c" \
  || fail "cannot build the QEMU insncount plugin (firmware-example/qemu-plugin/insncount.c)"

# --- lints of the firmware crate (it is outside the workspace, so test-all's fmt/clippy skip it) --
say "cargo fmt --check, cargo clippy (firmware crate)"
(cd "$FW" && cargo fmt --check) || fail "cargo fmt --check (run cargo fmt in firmware-example/)"

# --- frames: the demo run, recorded by the host tool --------------------------------------------
HOST_TARGET="${CARGO_TARGET_DIR:-$ROOT/target}"
say "building sds and monitor_replay (host)"
(cd "$ROOT" && cargo build -q --release -p sds-cli --bin sds -p sds-tests --bin monitor_replay)
SDS="$HOST_TARGET/release/sds"
REPLAY="$HOST_TARGET/release/monitor_replay"

# Alarm-worthy events in a host replay: collisions, lateral chunks, failed comfort chunks.
interesting() { grep -c -E '^event \{"(collision|lateral)"|^event \{"comfort".*true' "$1" || true; }

ROUTES=()
if [ -n "${FIRMWARE_FRAMES:-}" ]; then
  cp "$FIRMWARE_FRAMES" "$OUT/frames-custom.jsonl"
  ROUTES=(custom)
else
  "$SDS" demo "$OUT/demo" >/dev/null
  mapfile -t ids < <(grep -o '"route_id": *"[^"]*"' "$OUT/demo/results.json" | sed 's/.*"\([^"]*\)"$/\1/')
  [ ${#ids[@]} -gt 0 ] || fail "sds demo wrote no route ids in $OUT/demo/results.json"
  ranked=()
  for id in "${ids[@]}"; do
    "$SDS" frames --results "$OUT/demo/results.json" --telemetry "$OUT/demo/telemetry" \
      --routes "$OUT/demo/routes.xml" --route-id "$id" -o "$OUT/frames-$id.jsonl"
    "$REPLAY" "$OUT/frames-$id.jsonl" >"$OUT/host-$id.txt"
    ranked+=("$(interesting "$OUT/host-$id.txt") $id")
  done
  # Every demo route goes into flash, the one with the most events first (ties: the earlier
  # route): the measurements (bench, ticks) run on the first route.
  mapfile -t ROUTES < <(printf '%s\n' "${ranked[@]}" | sort -s -k1,1nr | cut -d' ' -f2)
  say "demo routes (alarm-worthy events): $(printf '%s\n' "${ranked[@]}" | sort -s -k1,1nr | paste -sd, -)"
fi
PRIMARY="${ROUTES[0]}"
FRAME_FILES=()
for r in "${ROUTES[@]}"; do FRAME_FILES+=("$OUT/frames-$r.jsonl"); done
SDS_FRAMES_LIST="$(IFS=:; echo "${FRAME_FILES[*]}")"
"$REPLAY" "${FRAME_FILES[@]}" >"$OUT/host.txt"
say "routes in flash: ${#ROUTES[@]} (measurements on $PRIMARY)"

# --- firmware builds ----------------------------------------------------------------------------
# build TARGET KIND [features...] -> $OUT/TARGET-KIND.elf (every route under test in flash)
build() {
  local target=$1 kind=$2
  shift 2
  local feats=()
  case $kind in
    report) feats=() ;;
    vehicle) feats=(--no-default-features) ;;
  esac
  if [ $# -gt 0 ]; then feats+=(--features "$*"); fi
  (cd "$FW" && SDS_FRAMES="$SDS_FRAMES_LIST" CARGO_TARGET_DIR="$FW_TARGET" \
    cargo build -q --release --target "$target" ${BUILD_STD[@]+"${BUILD_STD[@]}"} "${feats[@]}") \
    >"$OUT/build-$target-$kind.log" 2>&1 || return 1
  cp "$FW_TARGET/$target/release/firmware-example" "$OUT/$target-$kind.elf"
}

qemu() { # qemu TARGET ELF [args...]: runs the firmware with its semihosting arguments
  local target=$1 elf=$2
  shift 2
  local machine
  case $target in
    thumbv7em-none-eabihf) machine=(-cpu cortex-m4 -machine mps2-an386) ;;
    thumbv7m-none-eabi) machine=(-cpu cortex-m3 -machine lm3s6965evb) ;;
  esac
  local semi="enable=on,target=native,arg=firmware"
  for a in "$@"; do semi+=",arg=$a"; done
  timeout "$QEMU_TIMEOUT" qemu-system-arm "${machine[@]}" -nographic -monitor none -serial none \
    -icount shift=0 -semihosting-config "$semi" ${PLUGIN_ARGS[@]+"${PLUGIN_ARGS[@]}"} -kernel "$elf"
}

insns() { # insns TARGET ELF N: guest instructions of `bench N`
  local out="$OUT/insns-$1-$3.txt"
  PLUGIN_ARGS=(-plugin "$PLUGIN,out=$out")
  qemu "$1" "$2" bench "$3" >/dev/null || fail "$1: bench $3 exited with failure"
  PLUGIN_ARGS=()
  sed -n 's/^insns: //p' "$out"
}

explain_panics() { # lists the panicking branches left in the monitor path
  local target=$1
  build "$target" vehicle find-panics || return 0
  local elf="$OUT/$target-vehicle.elf"
  arm-none-eabi-objdump -d --no-show-raw-insn -C "$elf" \
    | sed -n 's/^ *\([0-9a-f]*\):[[:space:]]*bl[[:space:]].*<core::panicking::.*/\1/p' \
    | while read -r addr; do
      # Inlined frames, innermost first: function, then file:line.
      chain=$(arm-none-eabi-addr2line -f -i -C -e "$elf" "0x$addr" | paste - - | sed 's/(.*)//' \
        | awk -F'\t' '{ sub(/.*\//, "", $2); printf "%s%s (%s)", (NR > 1 ? " <- " : ""), $1, $2 }')
      # Skip the panic machinery's own calls (every frame in core::).
      if ! printf '%s\n' "$chain" | sed 's/ <- /\n/g' | grep -qv '^core::'; then continue; fi
      printf '  0x%s: %s\n' "$addr" "$chain" | cut -c1-400
    done >&2
}

PLUGIN_ARGS=()
{
  echo "# firmware measurements ($(date -u +%Y-%m-%d), $(rustc -V), $(qemu-system-arm --version | head -1))"
  echo "# routes in flash: ${ROUTES[*]}; measured: $PRIMARY ($(grep -c . "$OUT/frames-$PRIMARY.jsonl") frames)"
} >"$OUT/measurements.txt"
report() { echo "$*" | tee -a "$OUT/measurements.txt"; }

(cd "$FW" && SDS_FRAMES="$SDS_FRAMES_LIST" CARGO_TARGET_DIR="$FW_TARGET" \
  cargo clippy -q --release --target thumbv7em-none-eabihf ${BUILD_STD[@]+"${BUILD_STD[@]}"} -- -D warnings) \
  || fail "cargo clippy (firmware crate)"

# Proof 1 (both targets, every route under test) -----------------------------------------------
for target in "${TARGETS[@]}"; do
  build "$target" report || { cat "$OUT/build-$target-report.log" >&2; fail "$target: build"; }
  run="$OUT/run-$target-report.txt"
  qemu "$target" "$OUT/$target-report.elf" run >"$run" \
    || { tail -5 "$run" >&2; fail "$target: firmware exited with failure"; }
  grep -qx done "$run" || fail "$target: the firmware did not finish"
  grep -E '^(route|event|summary|pins) ' "$run" >"$OUT/fw-$target.txt" || true
  n=$(grep -c '^event ' "$OUT/host.txt" || true)
  [ "$n" -gt 0 ] || fail "the host replay has no event to compare"
  diff -u "$OUT/host.txt" "$OUT/fw-$target.txt" >&2 \
    || fail "proof 1: $target output differs from the host's"
  say "proof 1 ok: $target == host: ${#ROUTES[@]} routes, $n events, summaries and pins byte-identical"
done

# Proof 2: the monitor path links with the panic-never handler; a planted panic does not link ---
for target in "${TARGETS[@]}"; do
  if ! build "$target" vehicle; then
    grep -m1 -A2 'panicking branch survived' "$OUT/build-$target-vehicle.log" >&2 || tail -20 "$OUT/build-$target-vehicle.log" >&2
    echo "[firmware] panicking branches left (from a build with an ordinary panic handler):" >&2
    explain_panics "$target"
    fail "proof 2: $target: a panicking branch survives optimisation in the monitor path"
  fi
  say "proof 2 ok: $target: the monitor path links with the panic-never handler"
done
if build thumbv7em-none-eabihf vehicle panic-canary; then
  fail "proof 2: the planted panic (feature panic-canary) linked: the check cannot fail"
fi
grep -q 'panicking branch survived' "$OUT/build-thumbv7em-none-eabihf-vehicle.log" \
  || fail "proof 2: the planted panic failed to build for another reason (see $OUT/build-thumbv7em-none-eabihf-vehicle.log)"
say "proof 2 ok: a planted panic stops the link (the check can fail)"
# Rebuild the clean vehicle image (the canary build overwrote it).
build thumbv7em-none-eabihf vehicle || fail "rebuild"

# Proofs 3-5 per target ---------------------------------------------------------------------------
check() { # check LABEL VALUE MAX
  if [ "$2" -gt "$3" ]; then fail "$1 = $2 exceeds its budget $3 (budgets.sh)"; fi
}
section() { # section ELF NAME -> size in bytes (0 if absent)
  arm-none-eabi-size -A "$1" | awk -v s="$2" '$1 == s { print $2; f = 1 } END { if (!f) print 0 }'
}
for target in "${TARGETS[@]}"; do
  case $target in
    thumbv7em-none-eabihf) tag=M4F avg_max=$M4F_AVG_INSNS_MAX worst_max=$M4F_WORST_INSNS_MAX ;;
    thumbv7m-none-eabi) tag=M3 avg_max=$M3_AVG_INSNS_MAX worst_max=$M3_WORST_INSNS_MAX ;;
  esac
  report ""
  report "## $tag ($target)"
  # Proof 3: sizes.
  for kind in vehicle report; do
    elf="$OUT/$target-$kind.elf"
    vt=$(section "$elf" .vector_table)
    text=$(section "$elf" .text)
    rodata=$(section "$elf" .rodata)
    data=$(section "$elf" .data)
    bss=$(section "$elf" .bss)
    uninit=$(section "$elf" .uninit)
    table=$(arm-none-eabi-nm -S "$elf" | awk '$4 ~ /FRAME_TABLE/ { print $2 }')
    [ -n "$table" ] || fail "$target: FRAME_TABLE not found in $elf"
    table=$((16#$table))
    flash=$((vt + text + rodata + data))
    code=$((flash - table))
    ram=$((data + bss + uninit))
    report "sizes $kind: flash $flash (text $text, rodata $rodata incl. frame table $table, vectors $vt, data $data) = code $code + table $table; RAM $ram (data $data, bss $bss)"
    if [ "$kind" = vehicle ]; then check "$tag flash (vehicle, without table)" "$code" "$FLASH_CODE_MAX_VEHICLE"; fi
    if [ "$kind" = report ]; then check "$tag flash (report, without table)" "$code" "$FLASH_CODE_MAX_REPORT"; fi
    check "$tag RAM ($kind)" "$ram" "$RAM_MAX"
    # Proof 5: stack high-water mark of a whole run.
    qemu "$target" "$elf" run >"$OUT/run-$target-$kind.txt" || fail "$target $kind: run failed"
    stack=$(sed -n 's/^stack {"used":\([0-9]*\),.*/\1/p' "$OUT/run-$target-$kind.txt")
    msize=$(sed -n 's/^monitor_size //p' "$OUT/run-$target-$kind.txt")
    [ -n "$stack" ] && [ -n "$msize" ] || fail "$target $kind: no stack/monitor_size line"
    report "stack $kind: $stack bytes used (high-water mark of a whole run over every route, paint-stack)"
    if [ "$kind" = vehicle ]; then check "$tag stack (vehicle)" "$stack" "$STACK_MAX_VEHICLE"; fi
    if [ "$kind" = report ]; then check "$tag stack (report)" "$stack" "$STACK_MAX_REPORT"; fi
  done
  report "monitor state: $msize bytes (monitor_core::MONITOR_SIZE)"
  check "MONITOR_SIZE" "$msize" "$MONITOR_SIZE_MAX"

  # Proof 4: instructions per frame, on the vehicle image.
  elf="$OUT/$target-vehicle.elf"
  frames=$(grep -c . "$OUT/frames-$PRIMARY.jsonl")
  i0=$(insns "$target" "$elf" 0)
  iN=$(insns "$target" "$elf" "$frames")
  [ -n "$i0" ] && [ -n "$iN" ] || fail "$target: no instruction count (plugin)"
  total=$((iN - i0))
  avg10=$((total * 10 / frames))
  avg_int=$(((total + frames - 1) / frames))
  # Worst frame: SysTick (which advances with the instruction count under -icount) ranks the
  # frames; the three slowest are then counted exactly as insns(bench k+1) - insns(bench k).
  qemu "$target" "$elf" ticks >"$OUT/ticks-$target.txt" || fail "$target: ticks run failed"
  grep -qx done "$OUT/ticks-$target.txt" || fail "$target: ticks run did not finish"
  mapfile -t slow < <(awk '$1 == "ticks" { print $3, $2 }' "$OUT/ticks-$target.txt" | sort -k1,1nr -k2,2n | head -3 | cut -d' ' -f2)
  worst=0
  worst_frame=-1
  for k in "${slow[@]}"; do
    a=$(insns "$target" "$elf" "$k")
    b=$(insns "$target" "$elf" $((k + 1)))
    d=$((b - a))
    if [ "$d" -gt "$worst" ]; then
      worst=$d
      worst_frame=$k
    fi
  done
  # A plain frame for scale: the first frame of the second chunk.
  a=$(insns "$target" "$elf" 21)
  b=$(insns "$target" "$elf" 22)
  kind_of_worst="inside a chunk"
  if [ $(((worst_frame + 1) % 20)) -eq 0 ]; then kind_of_worst="a chunk end"; fi
  report "instructions: average $((avg10 / 10)).$((avg10 % 10)) per frame over $frames frames ($total in all); worst frame $worst (frame $worst_frame, $kind_of_worst); a plain frame $((b - a)); startup $i0"
  check "$tag average instructions per frame (rounded up)" "$avg_int" "$avg_max"
  check "$tag worst-frame instructions" "$worst" "$worst_max"
done

# Proof 6: the link checker on the Cortex-M4F.
# shellcheck source=link-checker/run-link.sh
source "$FW/link-checker/run-link.sh"

# Host unit tests of the firmware's library (frame table, pin rules, output lines).
say "host unit tests of the firmware library"
host=$(rustc -vV | sed -n 's/^host: //p')
(cd "$FW" && SDS_FRAMES="$SDS_FRAMES_LIST" CARGO_TARGET_DIR="$FW_TARGET" \
  cargo test -q --lib --target "$host") || fail "firmware library unit tests"

echo
say "measurements ($OUT/measurements.txt):"
cat "$OUT/measurements.txt"
say "all firmware proofs passed"
