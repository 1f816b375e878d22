#!/usr/bin/env bash
# Performance benchmarks of the SDS monitor: core (criterion + callgrind) and host replay
# (end to end, stage by stage, scaling). Prints one table of every figure against its goal.
# Not part of CI. Takes about 5 minutes on 2 cores; see docs/PERFORMANCE.md.
#
# Usage: bench/run.sh [--quick | --b2d]
#   --quick   a small large run (44 routes x 4,000 frames) and a short scaling series.
#   --b2d     only the ratio to Bench2Drive's comfort script (B2D_SCRIPT must be set): its one
#             run and sds score --jobs 1 (best of REPS) on the same B2D_ROUTES-route run, about
#             a minute instead of the whole bench.
# Environment:
#   CARGO_TARGET_DIR  cargo's target dir (default: target/ in the repository)
#   BENCH_DIR         where generated runs go (default: $CARGO_TARGET_DIR/bench-run); never committed
#   LARGE_ROUTES, LARGE_FRAMES  size of the large run (default 220 x 4000), in Bench2Drive's
#                     6-key frame layout (`sds demo --large`); a 13-key (`--layout wide`) run of
#                     WIDE_ROUTES (default 44) x LARGE_FRAMES is measured beside it
#   MID_ROUTES        routes of the mid-size run (default 128: 424 MB), whose peak RSS with
#                     --jobs 1 has a goal (<= 20 MB)
#   REPS              runs of each `sds score` measurement; the smallest CPU time (user + sys)
#                     and wall time are reported (default 5): other processes on a shared
#                     machine only ever add to them
#   B2D_SCRIPT        Bench2Drive's `tools/efficiency_smoothness_benchmark.py` (from a checkout of
#                     Bench2Drive; never copied into this repository: CC BY-NC-ND). When set, it
#                     runs once on a B2D_ROUTES-route run (default 44) through
#                     bench/b2d_smoothness.py, with numpy and scipy from a venv in
#                     $CARGO_TARGET_DIR/b2d-venv (made if missing), and the CPU ratio is reported;
#                     unset: that row says n/a
set -euo pipefail

cd "$(dirname "$0")/.."
ROOT=$(pwd)
TARGET=${CARGO_TARGET_DIR:-$ROOT/target}
export CARGO_TARGET_DIR=$TARGET
OUT=${BENCH_DIR:-$TARGET/bench-run}
QUICK=0; B2D_ONLY=0
[[ "${1:-}" == "--quick" ]] && QUICK=1
[[ "${1:-}" == "--b2d" ]] && B2D_ONLY=1
if [[ $B2D_ONLY == 1 && ! -f ${B2D_SCRIPT:-} ]]; then
    echo "bench: --b2d needs B2D_SCRIPT=<Bench2Drive>/tools/efficiency_smoothness_benchmark.py" >&2
    exit 2
fi
LARGE_ROUTES=${LARGE_ROUTES:-$([[ $QUICK == 1 ]] && echo 44 || echo 220)}
LARGE_FRAMES=${LARGE_FRAMES:-4000}
WIDE_ROUTES=${WIDE_ROUTES:-44}
MID_ROUTES=${MID_ROUTES:-$([[ $QUICK == 1 ]] && echo 22 || echo 128)}
REPS=${REPS:-5}
B2D_ROUTES=${B2D_ROUTES:-$([[ $QUICK == 1 ]] && echo 11 || echo 44)}
NPROC=$(nproc)
mkdir -p "$OUT"
LOG=$OUT/run.log
: >"$LOG"
say() { echo "bench: $*" >&2; }

# ---------------------------------------------------------------------------------------------
# Tools: GNU time (peak RSS) and valgrind (instruction counts), installed if missing.
need_apt=()
[[ -x /usr/bin/time ]] || need_apt+=(time)
command -v valgrind >/dev/null || need_apt+=(valgrind)
if ((${#need_apt[@]})); then
    if [[ $(id -u) == 0 ]] && command -v apt-get >/dev/null; then
        say "installing ${need_apt[*]}"
        apt-get update -qq >>"$LOG" 2>&1 || true
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${need_apt[@]}" >>"$LOG" 2>&1 || true
    else
        say "missing ${need_apt[*]} (not root): those figures are n/a"
    fi
fi
HAVE_TIME=0; [[ -x /usr/bin/time ]] && HAVE_TIME=1
HAVE_VG=0; command -v valgrind >/dev/null && HAVE_VG=1

# ---------------------------------------------------------------------------------------------
say "building (release)"
cargo build --release -p sds-cli --bin sds >>"$LOG" 2>&1
[[ $B2D_ONLY == 1 ]] || cargo bench -p monitor-host --no-run >>"$LOG" 2>&1
SDS=$TARGET/release/sds
bench_exe() { # newest executable of a bench target
    ls -t "$TARGET"/release/deps/"$1"-* 2>/dev/null | grep -v '\.d$' | head -n1
}
if [[ $B2D_ONLY == 0 ]]; then
    CORE_FRAMES=$(bench_exe core_frames)
    STAGES=$(bench_exe replay_stages)
fi

LOAD_START=$(cut -d' ' -f1-3 /proc/loadavg)
CPU_MODEL=$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//' || echo unknown)
MEM=$(awk '/MemTotal/ {printf "%.0f GiB", $2/1048576}' /proc/meminfo)

# Arithmetic helper: calc 'expr' -> number (awk, 1 decimal unless given a format).
calc() { awk "BEGIN { printf \"${2:-%.1f}\", $1 }"; }
# Status of a figure against a goal: ok 'measured <= goal' style conditions.
status() { awk "BEGIN { print (($1) ? \"met\" : \"NOT met\") }"; }

# ---------------------------------------------------------------------------------------------
if [[ $B2D_ONLY == 0 ]]; then
say "core: criterion (time per frame)"
cargo bench -p monitor-host --bench core -- --warm-up-time 1 --measurement-time 4 >>"$LOG" 2>&1
median_ns() { # criterion's median point estimate, ns per iteration: group bench
    grep -o '"median":{"confidence_interval":{[^}]*},"point_estimate":[0-9.e+-]*' \
        "$TARGET/criterion/$1/$2/new/estimates.json" | sed 's/.*://'
}
NS_AMORT=$(calc "$(median_ns core_cpu push_amortised) / 4000" %.2f)
NS_END=$(calc "$(median_ns core_cpu push_chunk_end)" %.1f)
NS_MID=$(calc "$(median_ns core_cpu push_mid_chunk)" %.1f)
NSW_AMORT=$(calc "$(median_ns core push_amortised) / 4000" %.2f)
NSW_END=$(calc "$(median_ns core push_chunk_end)" %.1f)
NSW_MID=$(calc "$(median_ns core push_mid_chunk)" %.1f)

IR_AMORT=n/a; IR_END=n/a; IR_MID=n/a
if [[ $HAVE_VG == 1 ]]; then
    say "core: callgrind (instructions per frame)"
    ir() {
        valgrind --tool=callgrind --callgrind-out-file=/dev/null --toggle-collect='*push_frames*' \
            "$CORE_FRAMES" "$1" 2>&1 | sed -n 's/.*Collected : *\([0-9]*\).*/\1/p'
    }
    I18=$(ir 18); I19=$(ir 19); I20=$(ir 20); I20K=$(ir 20000); I40K=$(ir 40000)
    IR_AMORT=$(calc "($I40K - $I20K) / 20000" %.1f)
    IR_END=$((I20 - I19))
    IR_MID=$((I19 - I18))
fi
fi

# ---------------------------------------------------------------------------------------------
# A generated run, reused while its size matches.
gen_run() { # dir routes frames [layout]
    local dir=$1 routes=$2 frames=$3 layout=${4:-b2d}
    # Reused only if written by this very sds binary (a changed generator writes it anew).
    if [[ -f $dir/.size && $(cat "$dir/.size") == "$routes x $frames $layout" && $dir/.size -nt $SDS ]]; then
        return
    fi
    rm -rf "$dir"
    "$SDS" demo "$dir" --large --large-routes "$routes" --large-frames "$frames" \
        --layout "$layout" >>"$LOG" 2>&1
    echo "$routes x $frames $layout" >"$dir/.size"
}
tel_bytes() { find "$1/telemetry" -name metric_info.json -printf '%s\n' | awk '{s += $1} END {print s}'; }
warm() { find "$1/telemetry" -name metric_info.json -exec cat {} + >/dev/null; }
# score DIR JOBS -> "wall cpu maxrss_kb": the smallest wall and the smallest CPU (user + sys) of
# REPS runs, and the largest peak RSS.
score() {
    local dir=$1 jobs=$2 w="" c="" r=0 line lw lu ls lr
    for _ in $(seq "$REPS"); do
        if [[ $HAVE_TIME == 1 ]]; then
            line=$(/usr/bin/time -f '%e %U %S %M' "$SDS" score --results "$dir/results.json" \
                --telemetry "$dir/telemetry" --routes "$dir/routes.xml" -o "$dir/report.json" \
                --jobs "$jobs" 2>&1 >/dev/null | tail -n1)
        else
            local t0 t1
            t0=$(date +%s.%N)
            "$SDS" score --results "$dir/results.json" --telemetry "$dir/telemetry" \
                --routes "$dir/routes.xml" -o "$dir/report.json" --jobs "$jobs" >/dev/null 2>&1
            t1=$(date +%s.%N)
            line="$(calc "$t1 - $t0" %.2f) 0 0 0"
        fi
        read -r lw lu ls lr <<<"$line"
        local lc
        lc=$(calc "$lu + $ls" %.2f)
        if [[ -z $w ]] || awk "BEGIN { exit !($lw < $w) }"; then w=$lw; fi
        if [[ -z $c ]] || awk "BEGIN { exit !($lc < $c) }"; then c=$lc; fi
        ((lr > r)) && r=$lr
    done
    echo "$w $c $r"
}

# cpu_fine DIR -> the smallest user + sys CPU seconds of REPS runs of `sds score --jobs 1`, to the
# microsecond (getrusage): GNU time truncates user and sys to 0.01 s each, up to 20 % of a
# 0.09 s run, too coarse for the ratio to Bench2Drive's script.
cpu_fine() {
    python3 - "$SDS" "$1" "$REPS" <<'PY'
import resource, subprocess, sys
sds, run, reps = sys.argv[1], sys.argv[2], int(sys.argv[3])
best = None
for _ in range(reps):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run([sds, "score", "--results", f"{run}/results.json", "--telemetry",
                    f"{run}/telemetry", "--routes", f"{run}/routes.xml", "-o",
                    f"{run}/report.json", "--jobs", "1"],
                   check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    best = cpu if best is None else min(best, cpu)
print(f"{best:.3f}")
PY
}

if [[ $B2D_ONLY == 0 ]]; then
LARGE=$OUT/large
say "host: large run ${LARGE_ROUTES} x ${LARGE_FRAMES} in $LARGE"
gen_run "$LARGE" "$LARGE_ROUTES" "$LARGE_FRAMES"
warm "$LARGE"
BYTES=$(tel_bytes "$LARGE")
FRAMES=$((LARGE_ROUTES * LARGE_FRAMES))
MB=$(calc "$BYTES / 1e6")
BPF=$(calc "$BYTES / $FRAMES" %.0f)

say "host: sds score --jobs 1 and --jobs $NPROC (each the best of $REPS runs)"
read -r W1 C1 R1 <<<"$(score "$LARGE" 1)"
read -r WN CN RN <<<"$(score "$LARGE" "$NPROC")"
MBS_CPU1=$(calc "$MB / $C1" %.0f)
MBS_W1=$(calc "$MB / $W1" %.0f)
MBS_WN=$(calc "$MB / $WN" %.0f)
FPS_W1=$(calc "$FRAMES / $W1 / 1e6" %.2f)
FPS_WN=$(calc "$FRAMES / $WN / 1e6" %.2f)
FPS_CPU1=$(calc "$FRAMES / $C1 / 1e6" %.2f)
SPEEDUP=$(calc "$W1 / $WN" %.2f)
CPU_RATIO=$(calc "$CN / $C1" %.2f)
RSS1=$(calc "$R1 / 1024" %.1f); RSSN=$(calc "$RN / 1024" %.1f)

RSS_THREAD=$(calc "($RN - $R1) / 1024 / ($NPROC - 1 + ($NPROC == 1))" %.1f)

WIDE=$OUT/wide
say "host: wide run (13 keys per frame) ${WIDE_ROUTES} x ${LARGE_FRAMES} in $WIDE"
gen_run "$WIDE" "$WIDE_ROUTES" "$LARGE_FRAMES" wide
warm "$WIDE"
WMB=$(calc "$(tel_bytes "$WIDE") / 1e6")
WBPF=$(calc "$(tel_bytes "$WIDE") / ($WIDE_ROUTES * $LARGE_FRAMES)" %.0f)
read -r _ WC _ <<<"$(score "$WIDE" 1)"
MBS_WIDE=$(calc "$WMB / $WC" %.0f)

MID=$OUT/mid
say "host: mid-size run ${MID_ROUTES} x ${LARGE_FRAMES} in $MID"
gen_run "$MID" "$MID_ROUTES" "$LARGE_FRAMES"
warm "$MID"
MMB=$(calc "$(tel_bytes "$MID") / 1e6")
read -r _ MC MR <<<"$(score "$MID" 1)"
MBS_MID=$(calc "$MMB / $MC" %.0f)
RSS_MID=$(calc "$MR / 1024" %.1f)
fi

# Bench2Drive's comfort script beside sds on the same run, CPU time of one invocation each (its
# one run takes half a minute; sds's figure is its best of REPS).
B2D_RATIO=n/a; B2D_CPU=n/a; B2D_RSS=n/a; B2D_SM=n/a; SDS_SM=n/a; B2C=n/a; BMB=n/a
if [[ -n ${B2D_SCRIPT:-} && -f ${B2D_SCRIPT:-} ]]; then
    B2D_PY=$TARGET/b2d-venv/bin/python
    if [[ ! -x $B2D_PY ]] || ! "$B2D_PY" -c 'import numpy, scipy' 2>/dev/null; then
        say "making $TARGET/b2d-venv (numpy, scipy) for Bench2Drive's script"
        { python3 -m venv "$TARGET/b2d-venv" && "$B2D_PY" -m pip install -q numpy scipy; } \
            >>"$LOG" 2>&1 || say "could not install numpy/scipy: Bench2Drive's row is n/a"
    fi
    if "$B2D_PY" -c 'import numpy, scipy' 2>/dev/null; then
        BRUN=$OUT/b2d
        gen_run "$BRUN" "$B2D_ROUTES" "$LARGE_FRAMES"
        warm "$BRUN"
        BMB=$(calc "$(tel_bytes "$BRUN") / 1e6")
        say "Bench2Drive's script on $B2D_ROUTES routes (one run, ~$((B2D_ROUTES * 3 / 4)) s)"
        line=$(/usr/bin/time -f '%U %S %M' "$B2D_PY" bench/b2d_smoothness.py "$B2D_SCRIPT" \
            "$BRUN/results.json" "$BRUN/telemetry" 2>"$OUT/b2d.time" | tail -n1)
        B2D_SM=${line#Driving Smoothness=}
        read -r bu bs br <<<"$(tail -n1 "$OUT/b2d.time")"
        B2D_CPU=$(calc "$bu + $bs" %.1f)
        B2D_RSS=$(calc "$br / 1024" %.0f)
        B2C=$(cpu_fine "$BRUN")
        SDS_SM=$(python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["summary"]["bench2drive"]["smoothness"])' "$BRUN/report.json")
        B2D_RATIO=$(calc "$B2D_CPU / $B2C" %.0f)
    fi
else
    say "B2D_SCRIPT not set: the ratio to Bench2Drive's script is n/a (see the header)"
fi

if [[ $B2D_ONLY == 1 ]]; then
    cat <<EOF

Load at start / end: $LOAD_START / $(cut -d' ' -f1-3 /proc/loadavg); $NPROC cores, $CPU_MODEL

| figure | measured | goal | status |
|---|---|---|---|
| Bench2Drive's comfort script / sds score --jobs 1, CPU, $B2D_ROUTES-route run ($BMB MB) | ${B2D_RATIO}x ($B2D_CPU s / $B2C s; smoothness $B2D_SM / $SDS_SM; its peak RSS $B2D_RSS MB) | >= 150x | $([[ $B2D_RATIO == n/a ]] && echo n/a || status "$B2D_RATIO >= 150") |
EOF
    exit 0
fi

say "host: stages (single thread, 3 runs: the smallest CPU time of each stage)"
: >"$OUT/stages.txt"; : >"$OUT/stages-wide.txt"
for _ in 1 2 3; do
    "$STAGES" "$LARGE" >>"$OUT/stages.txt"
    "$STAGES" "$WIDE" >>"$OUT/stages-wide.txt"
done
stage() { # name field [file]: the line of the run with the smallest cpu_s
    grep "^stage=$1 " "${3:-$OUT/stages.txt}" |
        awk '{ for (i = 1; i <= NF; i++) if ($i ~ /^cpu_s=/) { split($i, a, "="); print a[2], $0 } }' |
        sort -g | head -n1 | sed -n "s/.* $2=\([0-9.]*\).*/\1/p"
}
stage_mbs() { calc "$(stage "$1" bytes "${2:-}") / 1e6 / $(stage "$1" cpu_s "${2:-}")" %.0f; }
stage_nspf() { calc "$(stage "$1" cpu_s) * 1e9 / $(stage "$1" frames)" %.0f; }
stage_share() { calc "100 * $(stage "$1" cpu_s) / $(stage replay cpu_s)" %.1f; }

# ---------------------------------------------------------------------------------------------
if [[ $QUICK == 1 ]]; then
    SR=(1 11 22 44); SF=(1000 2000 4000); FR=11
else
    SR=(1 4 22 55 110 220); SF=(1000 2000 4000 8000); FR=27
fi
say "scaling: routes ${SR[*]} x 4000 frames; frames ${SF[*]} x $FR routes (--jobs 1)"
SCALE=$OUT/scale
mkdir -p "$SCALE"
scale_row() { # label dir
    local dir=$2 b f w r c
    warm "$dir"
    b=$(tel_bytes "$dir")
    f=$(($(cat "$dir/.size" | cut -d' ' -f1) * $(cat "$dir/.size" | cut -d' ' -f3)))
    read -r w c r <<<"$(score "$dir" 1)"
    # (time counts in 10 ms: a run that took less shows 0.00 and no rate)
    local nspf=- mbs=-
    if awk "BEGIN { exit !($c > 0) }"; then
        nspf=$(calc "$c * 1e9 / $f" %.0f)
        mbs=$(calc "$b / 1e6 / $c" %.0f)
    fi
    printf '| %s | %s | %s | %s | %s | %s | %s |\n' "$1" "$(calc "$b / 1e6" %.0f)" "$w" "$c" \
        "$nspf" "$mbs" "$(calc "$r / 1024" %.1f)"
}
ROWS_R=()
for n in "${SR[@]}"; do
    if [[ $n == "$LARGE_ROUTES" && $LARGE_FRAMES == 4000 ]]; then
        d=$LARGE
    else
        d=$SCALE/r$n
        gen_run "$d" "$n" 4000
    fi
    ROWS_R+=("$(scale_row "$n routes x 4000" "$d")")
    [[ $d == "$LARGE" ]] || rm -rf "$d"
done
ROWS_F=()
for f in "${SF[@]}"; do
    d=$SCALE/f$f
    gen_run "$d" "$FR" "$f"
    ROWS_F+=("$(scale_row "$FR routes x $f" "$d")")
    rm -rf "$d"
done
LOAD_END=$(cut -d' ' -f1-3 /proc/loadavg)

# ---------------------------------------------------------------------------------------------
cat <<EOF

## SDS performance ($(date -u +%Y-%m-%dT%H:%MZ), commit $(git rev-parse --short HEAD 2>/dev/null || echo '?'))
machine: $CPU_MODEL, $NPROC cores, $MEM; load average at start $LOAD_START, at end $LOAD_END
rustc: $(rustc --version); large run: $LARGE_ROUTES routes x $LARGE_FRAMES frames, Bench2Drive's 6-key layout, $MB MB of metric_info.json ($BPF B/frame); wide run: $WIDE_ROUTES x $LARGE_FRAMES, 13 keys, $WMB MB ($WBPF B/frame)
MB/s per core = bytes / (user + sys CPU seconds): unaffected by other processes; wall figures are. Every sds score figure is the smallest of $REPS runs (CPU and wall each), peak RSS the largest; stages the smallest of 3.

| figure | measured | goal | status |
|---|---|---|---|
| core: time per frame, amortised (criterion median, thread CPU time) | $NS_AMORT ns | <= 50 ns | $(status "$NS_AMORT <= 50") |
| core: time of the chunk-end (worst) frame (CPU time) | $NS_END ns | (report) | - |
| core: time of an ordinary frame (CPU time) | $NS_MID ns | (report) | - |
| core: the same three in wall time | $NSW_AMORT / $NSW_END / $NSW_MID ns | (report) | - |
| core: instructions per frame, amortised (callgrind) | $IR_AMORT | <= 300 | $([[ $IR_AMORT == n/a ]] && echo n/a || status "$IR_AMORT <= 300") |
| core: instructions of the chunk-end frame | $IR_END | (report) | - |
| core: instructions of an ordinary frame | $IR_MID | (report) | - |
| host: MB/s per core, end to end (--jobs 1, CPU time), $LARGE_ROUTES-route run ($MB MB) | $MBS_CPU1 MB/s | >= 1,300 MB/s | $(status "$MBS_CPU1 >= 1300") |
| host: the same on the $MID_ROUTES-route run ($MMB MB) | $MBS_MID MB/s | >= 1,300 MB/s | $(status "$MBS_MID >= 1300") |
| host: peak RSS, --jobs 1, $MID_ROUTES-route run ($MMB MB) | $RSS_MID MB | <= 20 MB | $(status "$RSS_MID <= 20") |
| Bench2Drive's comfort script / sds score --jobs 1, CPU, $B2D_ROUTES-route run ($BMB MB) | ${B2D_RATIO}x ($B2D_CPU s / $B2C s; smoothness $B2D_SM / $SDS_SM; its peak RSS $B2D_RSS MB) | >= 150x | $([[ $B2D_RATIO == n/a ]] && echo n/a || status "$B2D_RATIO >= 150") |
| parser: ours against the floor (serde_json IgnoredAny MB/s / ours, same bytes) | $(calc "100 * $(stage skip cpu_s) / $(stage parse cpu_s)" %.0f)% | >= 90% | $(status "$(stage skip cpu_s) / $(stage parse cpu_s) >= 0.9") |
| host: the same on the 13-key wide run | $MBS_WIDE MB/s | (report) | - |
| host: MB/s wall, --jobs 1 | $MBS_W1 MB/s ($W1 s) | (report) | - |
| host: MB/s wall, --jobs $NPROC | $MBS_WN MB/s ($WN s) | (report) | - |
| host: frames/s, --jobs 1 (CPU time / wall) | $FPS_CPU1 M / $FPS_W1 M | (report) | - |
| host: frames/s wall, --jobs $NPROC | $FPS_WN M | (report) | - |
| host: speed-up --jobs $NPROC over --jobs 1 (wall) | ${SPEEDUP}x | near $NPROC | $(status "$SPEEDUP >= 0.8 * $NPROC") |
| host: CPU seconds --jobs $NPROC / --jobs 1 (extra work of parallelism) | $CPU_RATIO | ~1.0 | $(status "$CPU_RATIO <= 1.15") |
| host: cores the OS gave us, --jobs 1 / --jobs $NPROC ((user + sys) / wall) | $(calc "$C1 / $W1" %.2f) / $(calc "$CN / $WN" %.2f) | (explains wall) | - |
| host: peak RSS, large run, --jobs 1 / --jobs $NPROC | $RSS1 / $RSSN MB | < 64 MB | $(status "$RSSN < 64 && $RSS1 < 64") |
| host: peak RSS per extra worker thread ((--jobs $NPROC - --jobs 1) / $((NPROC - 1))) | $RSS_THREAD MB | (report) | - |
| parser floor: serde_json IgnoredAny on the same bytes | $(stage_mbs skip) MB/s | (reference) | - |
| parser floor without holding the file: serde_json::from_reader, IgnoredAny | $(stage_mbs reader) MB/s | (reference) | - |
| parser: serde_json::Value DOM, first 20 routes | $(stage_mbs dom) MB/s | (reference) | - |
| parser: serde_json visitor alone (parse_metric_info_serde) | $(stage_mbs serde) MB/s | (reference) | - |
| parser: ours (parse_metric_info: scanner, serde on doubt) | $(stage_mbs parse) MB/s | (reference) | - |
| parser, wide run: skip floor / serde visitor / ours | $(stage_mbs skip "$OUT/stages-wide.txt") / $(stage_mbs serde "$OUT/stages-wide.txt") / $(stage_mbs parse "$OUT/stages-wide.txt") MB/s | (reference) | - |
| replay pipeline, single thread (replay::replay) | $(stage_mbs replay) MB/s | >= 300 MB/s | $(status "$(stage_mbs replay) >= 300") |

Stages of replay::replay, single thread, CPU time (large run):

| stage | ns/frame | MB/s | share of replay |
|---|---|---|---|
| read (std::fs::read, first touch) | $(stage_nspf read) | $(stage_mbs read) | $(stage_share read)% |
| skip (serde_json IgnoredAny: the parser floor) | $(stage_nspf skip) | $(stage_mbs skip) | $(stage_share skip)% |
| reader (the same through from_reader + BufReader) | $(stage_nspf reader) | $(stage_mbs reader) | $(stage_share reader)% |
| parse (metric_info::parse_metric_info) | $(stage_nspf parse) | $(stage_mbs parse) | $(stage_share parse)% |
| serde (parse_metric_info_serde, the visitor alone) | $(stage_nspf serde) | $(stage_mbs serde) | ($(stage_share serde)%) |
| prepare (speeds, lateral error, alignment, Frames) | $(stage_nspf prepare) | - | $(stage_share prepare)% |
| stream (Monitor::push over every frame) | $(stage_nspf stream) | - | $(stage_share stream)% |
| batch (batch::compute reference check) | $(stage_nspf batch) | - | $(stage_share batch)% |
| replay (all of it, incl. locate + read) | $(stage_nspf replay) | $(stage_mbs replay) | 100% |

Scaling (sds score --jobs 1; CPU = user + sys):

| run | MB | wall s | CPU s | CPU ns/frame | MB/s per core | peak RSS MB |
|---|---|---|---|---|---|---|
$(printf '%s\n' "${ROWS_R[@]}")
$(printf '%s\n' "${ROWS_F[@]}")
EOF
