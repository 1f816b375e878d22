# Proof 6 of firmware-example/run-tests.sh (sourced by it, after the demo run and `sds` are built;
# uses its OUT, FW_TARGET, SDS, PLUGIN, BUILD_STD and its say/fail/report/check/section helpers):
# the link checker image (firmware-example/link-checker) on the Cortex-M4F (mps2-an386).
#   a. lints and host unit tests of the checker crate; its release build links with the
#      panic-never handler (no panicking branch survives in the checker path);
#   b. live: QEMU serves the checker on UART0 as a TCP server; `sds link --to tcp:127.0.0.1:PORT`
#      plays the demo run into it, without faults and with every fault kind at a fixed seed
#      (a fresh checker each time: a doer that restarts its counters is a WRONGSEQUENCE); every
#      route must be equal to the replay over the frames the checker accepted (sds exits 0).
#      These two runs serve on the message-slot clock (`serve slots`: one frame period per
#      message received), so "the clean run raises no pin" holds however slowly a loaded host
#      runs the doer. A third run serves on SysTick (`serve`: the core idles in WFI and, under
#      -icount, virtual time runs with real time while it sleeps) and the doer stops sending for
#      2 s on one route played at the frame period (`--pace realtime --inject stall=2`):
#      NONEWDATA and the pin must show, the route still equal. With ../shared present, a real
#      route (generated along route 25300 of bench2drive220.xml, the real Town04 map) is played
#      clean and with faults: equal both times;
#   c. sizes, stack, and instructions per message (median and worst, exact with the insncount
#      plugin, ranked by SysTick as proof 4 does) within budgets.sh.

LC="$FW/link-checker"
LC_TARGET="$FW_TARGET/link-checker"
LC_ELF="$LC_TARGET/thumbv7em-none-eabihf/release/link-checker"
LC_INJECT="drop=0.02,corrupt=0.02,duplicate=0.02,reorder=0.02,stall=0.5,seed=7"

say "link checker: cargo fmt --check, clippy, host unit tests"
(cd "$LC" && cargo fmt --check) || fail "cargo fmt --check (run cargo fmt in firmware-example/link-checker/)"
(cd "$LC" && CARGO_TARGET_DIR="$LC_TARGET" cargo clippy -q --release ${BUILD_STD[@]+"${BUILD_STD[@]}"} -- -D warnings) \
  || fail "cargo clippy (link checker)"
host_triple=$(rustc -vV | sed -n 's/^host: //p')
(cd "$LC" && CARGO_TARGET_DIR="$LC_TARGET" cargo test -q --target "$host_triple") \
  || fail "link checker unit tests"

# The wire capture the measurements replay: the doer's bytes for the whole demo run, recorded
# against the host checker (the same bytes `sds link` writes to the board without faults).
rm -rf "$OUT/link-tap"
"$SDS" link --results "$OUT/demo/results.json" --telemetry "$OUT/demo/telemetry" \
  --to "exec:$SDS checker" --tap "$OUT/link-tap" -o "$OUT/link-host.json" 2>"$OUT/link-host.err" \
  || { cat "$OUT/link-host.err" >&2; fail "sds link into the host checker"; }
LC_MESSAGES=$(tr -cd '\000' <"$OUT/link-tap/sent.bin" | wc -c)

(cd "$LC" && SDS_LINK_WIRE="$OUT/link-tap/sent.bin" CARGO_TARGET_DIR="$LC_TARGET" \
  cargo build -q --release ${BUILD_STD[@]+"${BUILD_STD[@]}"}) >"$OUT/build-link-checker.log" 2>&1 || {
  grep -m1 -A2 'panicking branch survived' "$OUT/build-link-checker.log" >&2 || tail -20 "$OUT/build-link-checker.log" >&2
  fail "link checker: release build (a panicking branch survives in the checker path, or a build error)"
}
cp "$LC_ELF" "$OUT/link-checker.elf"
say "proof 6a ok: the link checker links with the panic-never handler"

# --- b. live, over a TCP character device --------------------------------------------------------
port_listening() { # is 127.0.0.1:$1 in LISTEN state? (/proc/net/tcp: hex port, state 0A)
  local hex
  hex=$(printf '%04X' "$1")
  awk -v p=":$hex" 'NR > 1 && $2 ~ p"$" && $4 == "0A" { f = 1 } END { exit !f }' /proc/net/tcp
}
LC_QEMU_PID=""
stop_checker() {
  if [ -n "$LC_QEMU_PID" ]; then
    kill "$LC_QEMU_PID" 2>/dev/null || true
    wait "$LC_QEMU_PID" 2>/dev/null || true
    LC_QEMU_PID=""
  fi
}
trap stop_checker EXIT
start_checker() { # start_checker LOG MODE...: a fresh checker in QEMU; sets LC_PORT and LC_QEMU_PID
  local log=$1 try
  shift
  local args
  args=$(printf ',arg=%s' "$@")
  for try in 1 2 3 4 5; do
    LC_PORT=$((20000 + (RANDOM % 20000)))
    port_listening "$LC_PORT" && continue
    timeout "$QEMU_TIMEOUT" qemu-system-arm -cpu cortex-m4 -machine mps2-an386 -nographic -monitor none \
      -chardev "socket,id=link,host=127.0.0.1,port=$LC_PORT,server=on,wait=off" -serial chardev:link \
      -icount shift=0 -semihosting-config "enable=on,target=native,arg=checker$args" \
      -kernel "$OUT/link-checker.elf" >"$log" 2>&1 &
    LC_QEMU_PID=$!
    # QEMU listens before the guest runs; wait for that (or for QEMU to give up on the port).
    local i
    for i in $(seq 1 300); do
      port_listening "$LC_PORT" && return 0
      kill -0 "$LC_QEMU_PID" 2>/dev/null || break
      sleep 0.1
    done
    stop_checker
  done
  cat "$log" >&2
  fail "link checker: QEMU did not listen on a TCP port (5 tries)"
}
play() { # play NAME CLOCK [sds link options]: the demo run into a fresh checker (CLOCK: serve
  # or slots); every route equal
  local name=$1 clock=$2
  shift 2
  if [ "$clock" = slots ]; then
    start_checker "$OUT/link-qemu-$name.txt" serve slots
  else
    start_checker "$OUT/link-qemu-$name.txt" serve
  fi
  local rc=0
  timeout "$QEMU_TIMEOUT" "$SDS" link --results "${LC_RESULTS:-$OUT/demo/results.json}" \
    --telemetry "${LC_TELEMETRY:-$OUT/demo/telemetry}" \
    --to "tcp:127.0.0.1:$LC_PORT" -o "$OUT/link-$name.json" "$@" 2>"$OUT/link-$name.err" || rc=$?
  stop_checker
  if [ "$rc" -ne 0 ]; then
    cat "$OUT/link-$name.err" >&2
    tail -5 "$OUT/link-qemu-$name.txt" >&2
    fail "proof 6b: sds link $* into the M4F checker: exit $rc (3: a route differs from the replay; see $OUT/link-$name.json)"
  fi
  grep -q '^route ' "$OUT/link-qemu-$name.txt" || fail "proof 6b: the checker printed no route line ($OUT/link-qemu-$name.txt)"
  say "proof 6b ok ($name): $(tail -1 "$OUT/link-$name.err")"
}
play clean slots
play faults slots --inject "$LC_INJECT"
# The faults run must have exercised the checker: frames dropped by it and link faults raised.
grep -q '"pin_rises":[1-9]' "$OUT/link-qemu-faults.txt" \
  || fail "proof 6b: the faults run raised no link_fault (pin) at all: the injection did not reach the checker"
if grep -q '"pin_rises":[1-9]' "$OUT/link-qemu-clean.txt"; then
  fail "proof 6b: the clean run raised the link_fault pin ($OUT/link-qemu-clean.txt)"
fi
statuses() { # statuses FILE STATUS: that status's count over the routes of a link report
  python3 -c 'import json, sys; print(sum(r["link"]["statuses"][sys.argv[2]] for r in json.load(open(sys.argv[1]))["routes"]))' "$1" "$2"
}
[ "$(statuses "$OUT/link-clean.json" NONEWDATA)" -eq 0 ] \
  || fail "proof 6b: NONEWDATA in the clean run on the message-slot clock ($OUT/link-clean.json)"
# A doer that stops sending, on the board's own clock: the core sleeps in WFI between bytes.
# One route at the frame period (at --pace fast the doer runs ahead of the board and its pause
# would fall on bytes still queued); the stall, 2 s of silence, is 13 timeouts of 150 ms, and a
# loaded host only makes it longer.
python3 -c 'import json, sys; d = json.load(open(sys.argv[1])); d["_checkpoint"]["records"] = d["_checkpoint"]["records"][:1]; json.dump(d, open(sys.argv[2], "w"))' \
  "$OUT/demo/results.json" "$OUT/link-one-route.json"
LC_RESULTS="$OUT/link-one-route.json" play stall serve --pace realtime --inject stall=2,seed=1
LC_NONEWDATA=$(statuses "$OUT/link-stall.json" NONEWDATA)
[ "$LC_NONEWDATA" -gt 0 ] \
  || fail "proof 6b: a doer silent for 2 s gave no NONEWDATA on the M4F checker ($OUT/link-stall.json)"
grep -q '"pin_rises":[1-9]' "$OUT/link-qemu-stall.txt" \
  || fail "proof 6b: a doer silent for 2 s raised no link_fault pin ($OUT/link-qemu-stall.txt)"
say "proof 6b ok (stall): NONEWDATA $LC_NONEWDATA times, the pin raised, the route equal"
# A real route: telemetry generated along route 25300 of bench2drive220.xml, scored against the
# real Town04 map (the run the host test link::i49_5 plays into `sds checker`, written out by it).
LC_SHARED="$FW/../../shared/fixtures"
if [ -f "$LC_SHARED/b2d/routes/bench2drive220.xml" ] && [ -f "$LC_SHARED/maps/Town04.xodr" ]; then
  rm -rf "$OUT/link-real-route"
  SDS_LINK_REAL_ROUTE_OUT="$OUT/link-real-route" cargo test -q --release -p sds-cli --test it -- \
    link::i49_5_real_route_and_map_through_the_link_equal_the_replay >"$OUT/link-real-route.log" 2>&1 \
    || { cat "$OUT/link-real-route.log" >&2; fail "proof 6b: the real route's host test (link::i49_5)"; }
  real=(--routes "$OUT/link-real-route/routes.xml" --maps "$LC_SHARED/maps" --set dt=0.05 --set lateral_reference=lane)
  LC_RESULTS="$OUT/link-real-route/results.json" LC_TELEMETRY="$OUT/link-real-route/telemetry" \
    play real slots "${real[@]}"
  LC_RESULTS="$OUT/link-real-route/results.json" LC_TELEMETRY="$OUT/link-real-route/telemetry" \
    play real-faults slots "${real[@]}" --inject "$LC_INJECT"
  python3 -c 'import json, sys; l = json.load(open(sys.argv[1]))["routes"][0]["link"]; sys.exit(not (l["equal"] and l["segments"] == 1 and l["events"] > 0 and sum(l["statuses"].values()) == l["statuses"]["OK"]))' \
    "$OUT/link-real.json" || fail "proof 6b: the real route's clean run is not whole and equal ($OUT/link-real.json)"
else
  say "note: proof 6b real route skipped: ../shared/fixtures (bench2drive220.xml, maps/Town04.xodr) absent"
fi

# --- c. sizes, stack, instructions per message ----------------------------------------------------
report ""
report "## link checker (M4F, thumbv7em-none-eabihf, mps2-an386)"
elf="$OUT/link-checker.elf"
vt=$(section "$elf" .vector_table)
text=$(section "$elf" .text)
rodata=$(section "$elf" .rodata)
data=$(section "$elf" .data)
bss=$(section "$elf" .bss)
uninit=$(section "$elf" .uninit)
wire=$(arm-none-eabi-nm -S "$elf" | awk '$4 ~ /WIRE/ { print $2 }')
[ -n "$wire" ] || fail "link checker: WIRE not found in $elf"
wire=$((16#$wire))
flash=$((vt + text + rodata + data))
code=$((flash - wire))
ram=$((data + bss + uninit))
report "sizes: flash $flash (text $text, rodata $rodata incl. the wire capture $wire, vectors $vt, data $data) = code $code + capture $wire; RAM $ram (data $data, bss $bss)"
check "link checker flash (without the capture)" "$code" "$LINK_FLASH_CODE_MAX"
check "link checker RAM" "$ram" "$RAM_MAX"
stack=0
for name in clean faults stall; do
  s=$(sed -n 's/.*"stack":\([0-9]*\)}.*/\1/p' "$OUT/link-qemu-$name.txt" | sort -n | tail -1)
  if [ -n "$s" ] && [ "$s" -gt "$stack" ]; then stack=$s; fi
done
[ "$stack" -gt 0 ] || fail "link checker: no stack figure in the serve runs"
report "stack: $stack bytes used (high-water mark of the serve runs, clean and with faults, paint-stack)"
check "link checker stack" "$stack" "$LINK_STACK_MAX"

i0=$(insns thumbv7em-none-eabihf "$elf" 0)
iN=$(insns thumbv7em-none-eabihf "$elf" "$LC_MESSAGES")
[ -n "$i0" ] && [ -n "$iN" ] || fail "link checker: no instruction count (plugin)"
total=$((iN - i0))
avg10=$((total * 10 / LC_MESSAGES))
qemu thumbv7em-none-eabihf "$elf" ticks >"$OUT/link-ticks.txt" || fail "link checker: ticks run failed"
grep -qx done "$OUT/link-ticks.txt" || fail "link checker: ticks run did not finish"
[ "$(grep -c '^ticks ' "$OUT/link-ticks.txt")" -eq "$LC_MESSAGES" ] || fail "link checker: ticks run: not one line per message"
# exact MESSAGE: instructions of message k, insns(bench k+1) - insns(bench k)
exact() { echo $(($(insns thumbv7em-none-eabihf "$elf" $(($1 + 1))) - $(insns thumbv7em-none-eabihf "$elf" "$1"))); }
mapfile -t ranked < <(awk '$1 == "ticks" { print $3, $2 }' "$OUT/link-ticks.txt" | sort -k1,1nr -k2,2n | cut -d' ' -f2)
worst=0
worst_msg=-1
for k in "${ranked[@]:0:3}"; do
  d=$(exact "$k")
  if [ "$d" -gt "$worst" ]; then
    worst=$d
    worst_msg=$k
  fi
done
median_msg=${ranked[$((LC_MESSAGES / 2))]}
median=$(exact "$median_msg")
report "instructions per message (received; its answers, the pin and the UART writes included): median $median (message $median_msg, the median by SysTick, counted exactly); worst $worst (message $worst_msg); average $((avg10 / 10)).$((avg10 % 10)) over $LC_MESSAGES messages ($total in all); startup $i0"
check "link checker median instructions per message" "$median" "$LINK_MEDIAN_INSNS_MAX"
check "link checker worst instructions per message" "$worst" "$LINK_WORST_INSNS_MAX"
for name in clean faults stall; do
  report "live ($name): $(tail -1 "$OUT/link-$name.err"); last route line: $(grep '^route ' "$OUT/link-qemu-$name.txt" | tail -1)"
done
trap - EXIT
