#!/usr/bin/env bash
# The C API's tests (called from scripts/test-all.sh). With every demo route of `sds demo`:
#   1. Rust: unit tests of sds-capi, and include/sds_monitor.h == cbindgen's output (tests/header.rs);
#   2. the shared library exports sds_* symbols only; the header compiles alone, warning-free, as
#      C99 and C++17 (-Wall -Wextra -Wpedantic -Werror);
#   3. install.sh into a scratch prefix; the example sds_replay is built against it with
#      pkg-config (gcc -std=c99 -Wall -Wextra -Werror, libsds_monitor.a linked statically);
#   4. host == C: the lines of the example, of the C test (test_api.c) and of the C++ test
#      (test_api.cpp, g++ -std=c++17 -Wall -Wextra -Werror) byte-identical to `monitor_replay`'s;
#      the two tests also check every error code (NULLs, small buffer, bad configs, NaN frames,
#      frame after finish); test_link.c: the live link's checker (sds_link_*) on the same routes
#      with a corrupted and a repeated frame gives the monitor's events and summaries;
#   4b. every demo route written as an MCAP log by an independent writer and replayed by sds_replay
#      from `sds frames --mcap`: the same verdicts as its telemetry (mcap-replay-test.sh);
#   5. the C and C++ tests run clean under valgrind (--error-exitcode=1 --leak-check=full); four
#      threads with a monitor each agree with a single-threaded run, with no race under helgrind;
#   6. Cortex-M4F: libsds_monitor.a for thumbv7em-none-eabihf linked into a C firmware
#      (arm-none-eabi-gcc, our own startup and semihosting) replays the same routes under QEMU
#      (mps2-an386, -icount shift=0) and prints lines byte-identical to `monitor_replay`'s (so to
#      the Rust firmware's, which firmware-example/run-tests.sh proves equal to them); sizes are
#      reported (target/capi-tests/measurements.txt; docs/C-API.md records them).
# Idempotent; everything it writes goes to target/capi-tests/. QEMU_TIMEOUT: seconds (default 60).
set -euo pipefail

HERE="$(cd "$(dirname "$0")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
TARGET_DIR="${CARGO_TARGET_DIR:-$ROOT/target}"
OUT="$TARGET_DIR/capi-tests"
QEMU_TIMEOUT="${QEMU_TIMEOUT:-60}"
M4F=thumbv7em-none-eabihf
START=$(date +%s)

say() { printf '[c-api] %s\n' "$*"; }
fail() {
  printf '[c-api] FAILED: %s\n' "$*" >&2
  exit 1
}
rm -rf "$OUT"
mkdir -p "$OUT"
cd "$ROOT"

# shellcheck source=../../scripts/skip.sh
source "$ROOT/scripts/skip.sh"
need_tools c-api gcc=gcc g++=g++ valgrind=valgrind pkg-config=pkg-config nm=binutils ldd=libc-bin \
  arm-none-eabi-gcc=gcc-arm-none-eabi arm-none-eabi-size=binutils-arm-none-eabi \
  arm-none-eabi-nm=binutils-arm-none-eabi qemu-system-arm=qemu-system-arm timeout=coreutils
[ -d "$(rustc --print sysroot)/lib/rustlib/$M4F/lib" ] \
  || loud_skip c-api "rust target $M4F missing: not tested (bash scripts/setup.sh adds it; by hand: rustup target add $M4F)"

# 1. Rust side ---------------------------------------------------------------------------------
say "cargo test -p sds-capi (unit tests; header == cbindgen output)"
cargo test -q --release -p sds-capi >"$OUT/cargo-test.log" 2>&1 \
  || { cat "$OUT/cargo-test.log" >&2; fail "cargo test -p sds-capi (a stale header: SDS_BLESS=1 cargo test -p sds-capi --release --test header)"; }
cargo build -q --release -p sds-capi

# 2. Symbols and the header alone -----------------------------------------------------------------
others=$(nm -D --defined-only "$TARGET_DIR/release/libsds_monitor.so" | awk '{ print $3 }' | grep -v '^sds_' || true)
[ -z "$others" ] || fail "libsds_monitor.so exports symbols without the sds_ prefix: $others"
nsym=$(nm -D --defined-only "$TARGET_DIR/release/libsds_monitor.so" | grep -c ' sds_')
printf '#include "sds_monitor.h"\n#include "sds_monitor.h" /* include guard */\nint main(void) { return sds_monitor_size() == 0; }\n' >"$OUT/header.c"
cp "$OUT/header.c" "$OUT/header.cpp"
gcc -std=c99 -Wall -Wextra -Wpedantic -Werror -I"$HERE/include" -o "$OUT/header-c" "$OUT/header.c" \
  "$TARGET_DIR/release/libsds_monitor.a" -lpthread -ldl -lm || fail "the header as C99"
g++ -std=c++17 -Wall -Wextra -Wpedantic -Werror -I"$HERE/include" -o "$OUT/header-cpp" "$OUT/header.cpp" \
  "$TARGET_DIR/release/libsds_monitor.a" -lpthread -ldl -lm || fail "the header as C++17"
# The example in docs/C-API.md compiles as shown and prints what the page says.
awk '/^```c$/ { on = 1; next } /^```$/ { if (on) exit } on' "$ROOT/docs/C-API.md" >"$OUT/doc-example.c"
gcc -std=c99 -Wall -Wextra -Wpedantic -Werror -I"$HERE/include" -o "$OUT/doc-example" "$OUT/doc-example.c" \
  "$TARGET_DIR/release/libsds_monitor.a" -lpthread -ldl -lm || fail "the example of docs/C-API.md does not compile"
"$OUT/doc-example" >"$OUT/doc-example.txt" || fail "the example of docs/C-API.md failed"
for want in "alarm: collision without braking at frame 60" "frames 100, comfort chunks 5/5, collisions without braking 1"; do
  grep -qxF "$want" "$OUT/doc-example.txt" || fail "the example of docs/C-API.md does not print: $want"
done
# The live link's example (the block after <!-- link-example -->) too.
awk '/^<!-- link-example -->$/ { want = 1; next } want && /^```c$/ { on = 1; next } on && /^```$/ { exit } on' \
  "$ROOT/docs/C-API.md" >"$OUT/doc-link-example.c"
gcc -std=c99 -Wall -Wextra -Wpedantic -Werror -I"$HERE/include" -o "$OUT/doc-link-example" "$OUT/doc-link-example.c" \
  "$TARGET_DIR/release/libsds_monitor.a" -lpthread -ldl -lm || fail "the live link example of docs/C-API.md does not compile"
"$OUT/doc-link-example" >"$OUT/doc-link-example.txt" || fail "the live link example of docs/C-API.md failed"
for want in "alarm: collision without braking on frame 60" "frames 99, OK 98, OKSOMELOST 1, ERROR 1"; do
  grep -qxF "$want" "$OUT/doc-link-example.txt" || fail "the live link example of docs/C-API.md does not print: $want"
done
say "ok: $nsym exported symbols, all sds_*; the header compiles warning-free as C99 and C++17; the docs examples run as documented"

# 3. Install, pkg-config ------------------------------------------------------------------------
bash "$HERE/install.sh" "$OUT/prefix" >/dev/null
for f in include/sds_monitor.h lib/libsds_monitor.a lib/libsds_monitor.so lib/pkgconfig/sds_monitor.pc; do
  [ -f "$OUT/prefix/$f" ] || fail "install.sh did not install $f"
done
export PKG_CONFIG_PATH="$OUT/prefix/lib/pkgconfig"
# --static: the .a, never the .so (pkg-config names -lsds_monitor; -Bstatic picks the archive).
PC_CFLAGS=$(pkg-config --cflags sds_monitor)
PC_LIBS=$(pkg-config --libs --static sds_monitor)
CFLAGS=(-std=c99 -Wall -Wextra -Werror -O2)
EX="$HERE/examples"
# shellcheck disable=SC2086
gcc "${CFLAGS[@]}" $PC_CFLAGS -I"$EX" -o "$OUT/sds_replay" "$EX/replay.c" "$EX/replay_file.c" \
  "$EX/sds_lines.c" "$EX/frames_jsonl.c" -Wl,-Bstatic -lsds_monitor -Wl,-Bdynamic $PC_LIBS \
  || fail "building the example against the installed library"
ldd "$OUT/sds_replay" >"$OUT/sds_replay.ldd"
! grep -q sds_monitor "$OUT/sds_replay.ldd" || fail "sds_replay links libsds_monitor dynamically"
say "ok: install.sh + pkg-config ($PC_LIBS); sds_replay linked statically"

# 4. Host replays --------------------------------------------------------------------------------
say "building sds and monitor_replay (host)"
cargo build -q --release -p sds-cli --bin sds -p sds-tests --bin monitor_replay
SDS="$TARGET_DIR/release/sds"
REPLAY="$TARGET_DIR/release/monitor_replay"
"$SDS" demo "$OUT/demo" >/dev/null 2>&1 || fail "sds demo"
mapfile -t ids < <(grep -o '"route_id": *"[^"]*"' "$OUT/demo/results.json" | sed 's/.*"\([^"]*\)"$/\1/')
[ ${#ids[@]} -gt 0 ] || fail "sds demo wrote no route ids"
# The Rust firmware's order: the route with the most alarm-worthy events first.
interesting() { grep -c -E '^event \{"(collision|lateral)"|^event \{"comfort".*true' "$1" || true; }
ranked=()
for id in "${ids[@]}"; do
  "$SDS" frames --results "$OUT/demo/results.json" --telemetry "$OUT/demo/telemetry" \
    --routes "$OUT/demo/routes.xml" --route-id "$id" -o "$OUT/frames-$id.jsonl"
  "$REPLAY" "$OUT/frames-$id.jsonl" >"$OUT/host-$id.txt"
  ranked+=("$(interesting "$OUT/host-$id.txt") $id")
done
mapfile -t ROUTES < <(printf '%s\n' "${ranked[@]}" | sort -s -k1,1nr | cut -d' ' -f2)
printf '%s\n' "${ROUTES[@]}" >"$OUT/routes.txt"
FRAMES=()
for r in "${ROUTES[@]}"; do FRAMES+=("$OUT/frames-$r.jsonl"); done
"$REPLAY" "${FRAMES[@]}" >"$OUT/host.txt"
nev=$(grep -c '^event ' "$OUT/host.txt" || true)
[ "$nev" -gt 0 ] || fail "the host replay has no event to compare"

LIBA="$TARGET_DIR/release/libsds_monitor.a"
SYSLIBS=(-lgcc_s -lutil -lrt -lpthread -lm -ldl -lc)
gcc "${CFLAGS[@]}" -I"$HERE/include" -I"$EX" -o "$OUT/test_api" "$HERE/ctest/test_api.c" \
  "$EX/replay_file.c" "$EX/sds_lines.c" "$EX/frames_jsonl.c" "$LIBA" "${SYSLIBS[@]}" || fail "building test_api.c"
gcc "${CFLAGS[@]}" -I"$HERE/include" -c -o "$OUT/frames_jsonl.o" "$EX/frames_jsonl.c"
g++ -std=c++17 -Wall -Wextra -Werror -O2 -I"$HERE/include" -I"$EX" -o "$OUT/test_api_cpp" \
  "$HERE/ctest/test_api.cpp" "$OUT/frames_jsonl.o" "$LIBA" "${SYSLIBS[@]}" || fail "building test_api.cpp"

"$OUT/sds_replay" "${FRAMES[@]}" >"$OUT/c-example.txt" || fail "sds_replay exited with failure"
diff -u "$OUT/host.txt" "$OUT/c-example.txt" >&2 || fail "the C example's lines differ from monitor_replay's"
"$OUT/test_api" "${FRAMES[@]}" >"$OUT/c-test.txt" 2>"$OUT/c-test.log" \
  || { cat "$OUT/c-test.log" >&2; fail "test_api.c"; }
diff -u "$OUT/host.txt" "$OUT/c-test.txt" >&2 || fail "the C test's lines differ from monitor_replay's"
"$OUT/test_api_cpp" "${FRAMES[@]}" >"$OUT/cpp-test.txt" 2>"$OUT/cpp-test.log" \
  || { cat "$OUT/cpp-test.log" >&2; fail "test_api.cpp"; }
diff -u "$OUT/host.txt" "$OUT/cpp-test.txt" >&2 || fail "the C++ test's lines differ from monitor_replay's"
say "ok: $(tail -1 "$OUT/c-test.log"); $(tail -1 "$OUT/cpp-test.log")"
say "ok: host == C example == C test == C++ test: ${#ROUTES[@]} routes, $nev events, summaries and pins byte-identical"
# 4a. The live link's checker from C (sds_link_*): every route encoded, with a corrupted and a
# repeated frame, through the caller-owned checker; its events and summary == sds_monitor's.
gcc "${CFLAGS[@]}" -I"$HERE/include" -I"$EX" -o "$OUT/test_link" "$HERE/ctest/test_link.c" \
  "$EX/frames_jsonl.c" "$LIBA" "${SYSLIBS[@]}" || fail "building test_link.c"
"$OUT/test_link" "${FRAMES[@]}" >"$OUT/c-link.txt" 2>"$OUT/c-link.log" \
  || { cat "$OUT/c-link.log" >&2; fail "test_link.c"; }
say "ok: $(tail -1 "$OUT/c-link.log") (the C checker's events and summaries == the monitor's on ${#ROUTES[@]} routes; ERROR, REPEATED, NONEWDATA, link_fault, link_restored)"
# 4b. The same routes as vehicle logs (MCAP, docs/SCORE.md §2.4) through the C example.
bash "$HERE/mcap-replay-test.sh" "$SDS" "$OUT/sds_replay" "$OUT/demo" "$OUT/mcap"

# 5. valgrind --------------------------------------------------------------------------------------
valgrind -q --error-exitcode=1 --leak-check=full --errors-for-leak-kinds=all \
  "$OUT/test_link" "${FRAMES[@]}" >"$OUT/test_link-valgrind.txt" 2>"$OUT/test_link-valgrind.log" \
  || { cat "$OUT/test_link-valgrind.log" >&2; fail "test_link under valgrind"; }
for t in test_api test_api_cpp; do
  valgrind -q --error-exitcode=1 --leak-check=full --errors-for-leak-kinds=all \
    "$OUT/$t" "${FRAMES[@]}" >"$OUT/$t-valgrind.txt" 2>"$OUT/$t-valgrind.log" \
    || { cat "$OUT/$t-valgrind.log" >&2; fail "$t under valgrind"; }
  cmp -s "$OUT/host.txt" "$OUT/$t-valgrind.txt" || fail "$t under valgrind printed other lines"
done
gcc "${CFLAGS[@]}" -pthread -I"$HERE/include" -o "$OUT/test_threads" "$HERE/ctest/test_threads.c" "$LIBA" \
  "${SYSLIBS[@]}" || fail "building test_threads.c"
valgrind -q --tool=helgrind --error-exitcode=1 "$OUT/test_threads" 2>"$OUT/test_threads.log" \
  || { cat "$OUT/test_threads.log" >&2; fail "test_threads under helgrind (a data race, or a thread's result differs)"; }
say "ok: test_api, test_api_cpp and test_link clean under valgrind (no error, no leak); $(tail -1 "$OUT/test_threads.log") (one monitor per thread, no data race under helgrind)"

# 6. Cortex-M4F under QEMU ---------------------------------------------------------------------------
bash "$HERE/install.sh" "$OUT/prefix-m4f" --target "$M4F" >"$OUT/build-m4f.log" 2>&1 \
  || { cat "$OUT/build-m4f.log" >&2; fail "building libsds_monitor.a for $M4F"; }
gcc "${CFLAGS[@]}" -I"$HERE/include" -I"$EX" -o "$OUT/frames2c" "$HERE/firmware/frames2c.c" "$EX/frames_jsonl.c"
"$OUT/frames2c" "$OUT/fw_frames.c" "${FRAMES[@]}"
FWDIR="$HERE/firmware"
ARMFLAGS=(-std=c99 -Wall -Wextra -Werror -O2 -mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16
  -ffreestanding -ffunction-sections -fdata-sections -nostdlib)
arm-none-eabi-gcc "${ARMFLAGS[@]}" -I"$OUT/prefix-m4f/include" -I"$EX" -I"$FWDIR" -T "$FWDIR/link.ld" \
  -Wl,--gc-sections -Wl,-z,noexecstack -Wl,-Map="$OUT/fw.map" -o "$OUT/fw-m4f.elf" \
  "$FWDIR/startup.c" "$FWDIR/semihost.c" "$FWDIR/main.c" "$EX/sds_lines.c" "$OUT/fw_frames.c" \
  "$OUT/prefix-m4f/lib/libsds_monitor.a" -lgcc || fail "linking the C firmware"
timeout "$QEMU_TIMEOUT" qemu-system-arm -cpu cortex-m4 -machine mps2-an386 -nographic -monitor none \
  -serial none -icount shift=0 -semihosting-config enable=on,target=native -kernel "$OUT/fw-m4f.elf" \
  >"$OUT/fw-run.txt" || { tail -5 "$OUT/fw-run.txt" >&2; fail "the C firmware exited with failure under QEMU"; }
grep -qx done "$OUT/fw-run.txt" || fail "the C firmware did not finish"
grep -E '^(route|event|summary|pins) ' "$OUT/fw-run.txt" >"$OUT/fw-m4f.txt" || true
diff -u "$OUT/host.txt" "$OUT/fw-m4f.txt" >&2 || fail "the C firmware's lines (Cortex-M4F) differ from monitor_replay's"
say "ok: Cortex-M4F C firmware == host: ${#ROUTES[@]} routes, $nev events, summaries and pins byte-identical"
# And directly against the Rust firmware's own output, when firmware-example/run-tests.sh ran
# before (scripts/test-all.sh runs it first) on the same routes in the same order.
RUST_FW="$ROOT/firmware-example/target/qemu-tests"
if [ -f "$RUST_FW/fw-$M4F.txt" ] && [ -f "$RUST_FW/host.txt" ] && cmp -s "$RUST_FW/host.txt" "$OUT/host.txt"; then
  diff -u "$RUST_FW/fw-$M4F.txt" "$OUT/fw-m4f.txt" >&2 || fail "the C firmware's lines differ from the Rust firmware's ($RUST_FW/fw-$M4F.txt)"
  say "ok: Cortex-M4F C firmware == Rust firmware (firmware-example, its last run): byte-identical"
else
  say "note: no output of the Rust firmware on these routes (firmware-example/run-tests.sh not run): compared with the host only"
fi

# No panicking code in the image: the panic handler (a `udf` trap) and every panic path were
# removed as unreachable. The check can fail: the test-only feature panic-canary adds a panic
# the optimiser cannot remove; its image must contain the trap, and running it must end in the
# firmware's fault handler (a panic never returns into C).
has_panic() { # (files, not pipes: grep -q would end the pipe early, and pipefail would see SIGPIPE)
  arm-none-eabi-objdump -d "$1" >"$1.dis"
  arm-none-eabi-nm -C "$1" >"$1.nm"
  grep -qE $'\tudf(\\.w)?\t' "$1.dis" || grep -qi panic "$1.nm"
}
! has_panic "$OUT/fw-m4f.elf" || fail "panicking code survives in the Cortex-M4F image (see arm-none-eabi-objdump -d $OUT/fw-m4f.elf | grep udf)"
(CARGO_PROFILE_RELEASE_LTO=fat CARGO_PROFILE_RELEASE_CODEGEN_UNITS=1 cargo rustc -q --release -p sds-capi \
  --target "$M4F" --crate-type staticlib --features panic-canary) >"$OUT/build-canary.log" 2>&1 \
  || { cat "$OUT/build-canary.log" >&2; fail "building the panic canary"; }
arm-none-eabi-gcc "${ARMFLAGS[@]}" -DSDS_PANIC_CANARY -I"$HERE/include" -I"$EX" -I"$FWDIR" -T "$FWDIR/link.ld" \
  -Wl,--gc-sections -Wl,-z,noexecstack -o "$OUT/fw-canary.elf" "$FWDIR/startup.c" "$FWDIR/semihost.c" \
  "$FWDIR/main.c" "$EX/sds_lines.c" "$OUT/fw_frames.c" "$TARGET_DIR/$M4F/release/libsds_monitor.a" -lgcc \
  || fail "linking the panic canary firmware"
has_panic "$OUT/fw-canary.elf" || fail "the planted panic left no trace in the image: the check above cannot fail"
if timeout "$QEMU_TIMEOUT" qemu-system-arm -cpu cortex-m4 -machine mps2-an386 -nographic -monitor none \
  -serial none -icount shift=0 -semihosting-config enable=on,target=native -kernel "$OUT/fw-canary.elf" \
  >"$OUT/fw-canary.txt"; then
  fail "the panic canary firmware exited successfully"
fi
grep -q '^error: fault' "$OUT/fw-canary.txt" || fail "the planted panic did not trap into the fault handler ($OUT/fw-canary.txt)"
say "ok: no panicking code in the Cortex-M4F image; a planted panic shows (udf) and traps into the fault handler"

# Sizes: sections of the image; the library's share by symbol (every symbol of the image that
# libsds_monitor.a defines), its float formatting (Ryu, for the JSON lines) apart.
section() { arm-none-eabi-size -A "$1" | awk -v s="$2" '$1 == s { print $2; f = 1 } END { if (!f) print 0 }'; }
ELF="$OUT/fw-m4f.elf"
text=$(section "$ELF" .text)
rodata=$(section "$ELF" .rodata)
vectors=$(section "$ELF" .vectors)
data=$(section "$ELF" .data)
bss=$(section "$ELF" .bss)
table=$(arm-none-eabi-nm -S -t d "$ELF" | awk '$4 == "fw_frames" { print $2 + 0 }')
[ -n "$table" ] || fail "fw_frames not found in the image"
arm-none-eabi-nm --defined-only "$OUT/prefix-m4f/lib/libsds_monitor.a" 2>/dev/null | awk 'NF == 3 { print $3 }' | sort -u >"$OUT/lib-symbols.txt"
arm-none-eabi-nm -S -t d "$ELF" | awk 'NF == 4 { print $4, $2 + 0, $3 }' | sort >"$OUT/image-symbols.txt"
lib_total=$(join "$OUT/image-symbols.txt" "$OUT/lib-symbols.txt" | awk '{ s += $2 } END { print s + 0 }')
lib_format=$(join "$OUT/image-symbols.txt" "$OUT/lib-symbols.txt" | awk '$1 ~ /ryu|sds_format_f/ { s += $2 } END { print s + 0 }')
# compiler_builtins' objects (memcpy/memset, soft f64 compares) are not readable by binutils' nm
# in the archive: take them from the image by name.
builtins=$(awk '$1 ~ /compiler_builtins|^__aeabi_/ { s += $2 } END { print s + 0 }' "$OUT/image-symbols.txt")
msize=$(sed -n 's/^monitor_size //p' "$OUT/fw-run.txt")
malign=$(sed -n 's/^monitor_align //p' "$OUT/fw-run.txt")
ssize=$(sed -n 's/^storage_size //p' "$OUT/fw-run.txt")
stack=$(sed -n 's/^stack //p' "$OUT/fw-run.txt")
# Instructions per frame through the C API (QEMU's insncount plugin; -icount shift=0 makes the
# counts repeatable): `bench N` pushes the first N frames of the first route and exits.
# The project's own plugin (firmware-example/qemu-plugin/, the one the Rust firmware is counted with).
PLUGIN_SRC="$ROOT/firmware-example/qemu-plugin/insncount.c"
gcc -shared -fPIC -O2 -Wall -Wextra -Werror -fvisibility=hidden -o "$OUT/libinsncount.so" "$PLUGIN_SRC" \
  || fail "building the QEMU insncount plugin ($PLUGIN_SRC)"
insns() {
  timeout "$QEMU_TIMEOUT" qemu-system-arm -cpu cortex-m4 -machine mps2-an386 -nographic -monitor none \
    -serial none -icount shift=0 -semihosting-config "enable=on,target=native,arg=fw,arg=bench,arg=$1" \
    -plugin "$OUT/libinsncount.so,out=$OUT/insns-$1.txt" -kernel "$ELF" >/dev/null \
    || fail "the C firmware's bench $1 failed"
  sed -n 's/^insns: //p' "$OUT/insns-$1.txt"
}
nfirst=$(sed -n 's/^const uint32_t fw_route_frames\[\] = {\([0-9]*\).*/\1/p' "$OUT/fw_frames.c")
i0=$(insns 0); iN=$(insns "$nfirst"); i19=$(insns 19); i20=$(insns 20); i21=$(insns 21); i22=$(insns 22)
avg10=$(((iN - i0) * 10 / nfirst))
insns_line="instructions through the C API: average $((avg10 / 10)).$((avg10 % 10)) per frame over route ${ROUTES[0]} ($nfirst frames), a chunk end (frame 19) $((i20 - i19)), a plain frame (21) $((i22 - i21))"
{
  echo "# C API on Cortex-M4F ($(date -u +%Y-%m-%d), $(rustc -V), $(arm-none-eabi-gcc --version | head -1))"
  echo "image: flash $((vectors + text + rodata + data)) bytes (text $text, rodata $rodata incl. frame table $table, vectors $vectors, data $data) = code $((vectors + text + rodata + data - table)) + table $table; RAM $((data + bss)) (bss $bss, of which the monitor storage $ssize) + stack"
  echo "libsds_monitor.a in the image: $((lib_total + builtins)) bytes (code and constants): monitor path $((lib_total - lib_format)), float text (sds_format_f32, Ryu tables) $lib_format, runtime helpers (compiler_builtins: memcpy, memset, f64 compares) $builtins"
  echo "monitor state: sds_monitor_size() = $msize bytes, align $malign (sds_monitor_storage: $ssize bytes)"
  echo "$insns_line"
  echo "stack: $stack bytes used by the whole run (paint high-water mark; includes two 640-byte line buffers)"
} >"$OUT/measurements.txt"
sed 's/^/[c-api]   /' "$OUT/measurements.txt"
say "all C API checks passed in $(($(date +%s) - START)) s"
