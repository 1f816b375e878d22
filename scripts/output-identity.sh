#!/usr/bin/env bash
# Output identity check for refactors: every report, table, page and trace `sds` writes, on the
# built-in demo and on every real fixture, captured into one folder; two such folders diffed.
#
#   scripts/output-identity.sh capture DIR [SDS]
#                                             build sds (release), write all outputs into DIR;
#                                             with SDS, run that binary instead (no build)
#   scripts/output-identity.sh diff BEFORE AFTER
#                                             diff -r the two folders, print a one-line summary
#                                             (exit 0 when identical, 1 otherwise)
#
# Typical use: capture on the base commit into /tmp/ident-before, change the code, capture into
# /tmp/ident-after, then diff. Or, for a branch against main, from the branch's checkout:
#   scripts/output-identity.sh capture /tmp/ident-main /work/main/target/release/sds
#   scripts/output-identity.sh capture /tmp/ident-branch
#   scripts/output-identity.sh diff /tmp/ident-main /tmp/ident-branch
# What is captured: score in every format (and its file outputs: traces, figures, long tables,
# rerun list and XML, protocols, groupings), frames, compare, merge, watch's final report (one
# round) and link's report (latencies masked: they are wall-clock times). Every command runs from the repository root with relative paths
# (scratch folder target/ident-work), so the paths reports embed are the same in any checkout.
# Each run's stdout, stderr and exit code are kept: errors and warnings are behaviour too.
# The real fixtures live in ../shared/fixtures; without them only the demo part runs (said loudly).
set -euo pipefail

usage() {
    echo "usage: $0 capture DIR | diff BEFORE AFTER" >&2
    exit 2
}

[ $# -ge 1 ] || usage
mode=$1
shift

if [ "$mode" = diff ]; then
    [ $# -eq 2 ] || usage
    before=$1
    after=$2
    files=$(cd "$before" && find . -type f | wc -l)
    set +e
    out=$(diff -r "$before" "$after")
    rc=$?
    set -e
    if [ $rc -ge 2 ]; then
        echo "$out" >&2
        echo "output-identity: diff failed" >&2
        exit 2
    fi
    # One line per differing file or per file present on one side only.
    ndiff=$(printf '%s\n' "$out" | grep -cE '^(diff -r|Only in|Binary files)' || true)
    if [ "$ndiff" -gt 0 ]; then
        printf '%s\n' "$out" | head -200
    fi
    echo "output-identity: compared $files files ($before vs $after): $ndiff differences"
    [ "$ndiff" -eq 0 ]
    exit $?
fi

[ "$mode" = capture ] || usage
[ $# -eq 1 ] || [ $# -eq 2 ] || usage
dest=$1
sds=${2:-}
if [ -n "$sds" ]; then
    [ -x "$sds" ] || { echo "output-identity: $sds is not an executable sds binary" >&2; exit 2; }
    sds=$(cd "$(dirname "$sds")" && pwd)/$(basename "$sds")
fi

root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
if [ -z "$sds" ]; then
    cargo build -q --release -p sds-cli --bin sds
    sds=target/release/sds
fi
echo "output-identity: capturing with $sds" >&2
work=target/ident-work
rm -rf "$work"
mkdir -p "$work/out"

# run NAME ARGS...: run sds, keep stdout, stderr and the exit code as out/NAME.{stdout,stderr,rc}.
run() {
    local name=$1
    shift
    set +e
    "$sds" "$@" >"$work/out/$name.stdout" 2>"$work/out/$name.stderr"
    echo $? >"$work/out/$name.rc"
    set -e
}

formats="json table markdown latex csv html"

# --- The built-in demo, scored with its town map -------------------------------------------
demo=$work/demo
run demo.write demo "$demo" --force
demo_in=(--results "$demo/results.json" --telemetry "$demo/telemetry" --routes "$demo/routes.xml")
for f in $formats; do
    run "demo.maps.$f" score "${demo_in[@]}" --maps "$demo/maps" --format "$f"
    run "demo.nomaps.$f" score "${demo_in[@]}" --format "$f"
done
run demo.legacy.json score "${demo_in[@]}" --maps "$demo/maps" --profile b2d-legacy
for g in scenario town weather; do
    for f in json table csv; do
        run "demo.group-$g.$f" score "${demo_in[@]}" --maps "$demo/maps" --group-by "$g" --format "$f"
    done
done
printf 'route,label\n900001,easy\n900002,hard\nRouteScenario_900005_rep0,hard\n' >"$work/labels.csv"
run demo.group-route.json score "${demo_in[@]}" --group-by route --labels "$work/labels.csv"
run demo.group-route.table score "${demo_in[@]}" --group-by route --labels "$work/labels.csv" --format table
run demo.traces score "${demo_in[@]}" --maps "$demo/maps" --traces "$work/out/demo.traces.d" --format json
run demo.output score "${demo_in[@]}" --maps "$demo/maps" --format html -o "$work/out/demo.output.html"
run demo.nodemotelemetry score --results "$demo/results.json" --routes "$demo/routes.xml"
run demo.frames frames "${demo_in[@]}" --route-id RouteScenario_900005_rep0
run demo.frames-nolat frames --results "$demo/results.json" --telemetry "$demo/telemetry" \
    --route-id RouteScenario_900001_rep0
for f in json table markdown latex html; do
    run "demo.compare.$f" compare "a=$demo/results.json" "b=$demo/results.json" \
        --routes "$demo/routes.xml" --maps "$demo/maps" --format "$f"
done
# score's other file outputs, and the protocols.
run demo.files score "${demo_in[@]}" --maps "$demo/maps" --tables "$work/out/demo.tables.d" \
    --figures "$work/out/demo.figures.d" --rerun-list "$work/out/demo.rerun.txt" \
    --rerun-xml "$work/out/demo.rerun.xml" -o "$work/out/demo.files.json"
for f in json table csv; do
    run "demo.protocol.$f" score "${demo_in[@]}" --protocol all --format "$f"
done
# merge: the demo's JSON report as the one part, in every format.
run demo.part score "${demo_in[@]}" --maps "$demo/maps" -o "$work/demo.part.json"
for f in $formats; do
    run "demo.merge.$f" merge "$work/demo.part.json" --format "$f"
done
run demo.merge.files merge "$work/demo.part.json" --tables "$work/out/demo.merge.tables.d" \
    --rerun-list "$work/out/demo.merge.rerun.txt"
# watch: one round, its final report and status lines.
for f in json table; do
    run "demo.watch.$f" watch "${demo_in[@]}" --maps "$demo/maps" --once --format "$f" \
        -o "$work/out/demo.watch.$f.report"
done
run demo.watch.status watch "${demo_in[@]}" --once --status-json -o "$work/demo.watch.status.json"
# The status line's clock time and the round's duration are wall-clock: masked.
python3 - "$work/out/demo.watch.status.stderr" <<'EOF'
import json, sys
lines = []
with open(sys.argv[1]) as f:
    for line in f:
        try:
            status = json.loads(line)
        except ValueError:
            lines.append(line.rstrip("\n"))
            continue
        for key in ("time", "round_ms"):
            if key in status:
                status[key] = "<wall clock>"
        lines.append(json.dumps(status))
with open(sys.argv[1], "w") as f:
    f.write("".join(line + "\n" for line in lines))
EOF
# link: played to sds's own checker, without and with (seeded) faults. The checker is named by
# a link in the scratch folder, so the report's `to` is the same whichever binary runs; its
# latencies are wall-clock times: masked before the diff.
mkdir -p "$work/bin"
ln -sf "$(cd "$(dirname "$sds")" && pwd)/$(basename "$sds")" "$work/bin/sds"
run demo.link link "${demo_in[@]}" --maps "$demo/maps" --to "exec:$work/bin/sds checker" \
    -o "$work/out/demo.link.json"
run demo.link-faults link "${demo_in[@]}" --to "exec:$work/bin/sds checker" \
    --inject drop=0.02,corrupt=0.02,duplicate=0.02,reorder=0.02,seed=7 \
    -o "$work/out/demo.link-faults.json"
for r in "$work"/out/demo.link*.json; do
    [ -f "$r" ] || continue
    python3 - "$r" <<'EOF'
import json, sys
def mask(v):
    if isinstance(v, dict):
        return {k: ("<wall clock>" if k == "latency_ms" else mask(x)) for k, x in v.items()}
    if isinstance(v, list):
        return [mask(x) for x in v]
    return v
with open(sys.argv[1]) as f:
    report = json.load(f)
with open(sys.argv[1], "w") as f:
    json.dump(mask(report), f, indent=2)
EOF
done

# --- Every real fixture ----------------------------------------------------------------------
b2d=../shared/fixtures/b2d
maps=../shared/fixtures/maps
if [ ! -d "$b2d" ]; then
    echo "output-identity: SKIPPING the real fixtures: $b2d is absent (only the demo was captured)" >&2
    echo "SKIPPED: $b2d absent" >"$work/out/fixtures.SKIPPED"
else
    xml=$b2d/routes/bench2drive220.xml
    weather=$b2d/routes/weather.xml
    inputs=()
    for p in "$b2d"/*.json "$b2d"/lead_tfv6_per_route "$b2d"/tfpp_raw_shards; do
        inputs+=("$p")
    done
    for p in "${inputs[@]}"; do
        n=$(basename "$p" .json)
        common=(--results "$p" --routes "$xml" --allow-missing-telemetry)
        for f in $formats; do
            run "fx.$n.$f" score "${common[@]}" --format "$f"
        done
        # Without --allow-missing-telemetry (no real metric_info.json exists: every route missing).
        run "fx.$n.strict" score --results "$p" --routes "$xml"
        run "fx.$n.noroutes" score --results "$p" --allow-missing-telemetry --expected-routes 220
        run "fx.$n.weather.table" score "${common[@]}" --group-by weather --weathers "$weather" \
            --infraction collisions_vehicle --format table
        run "fx.$n.town.csv" score "${common[@]}" --group-by town --format csv
    done
    tfpp=$b2d/carla_garage_tfpp_b2d_traj_merged.json
    common=(--results "$tfpp" --routes "$xml" --allow-missing-telemetry)
    for f in json table html; do
        run "fx.tfpp.maps.$f" score "${common[@]}" --maps "$maps" --format "$f"
    done
    run fx.tfpp.traces score "${common[@]}" --maps "$maps" --traces "$work/out/fx.tfpp.traces.d"
    run fx.tfpp.scenario.markdown score "${common[@]}" --group-by scenario --format markdown
    run fx.tfpp.scenario.latex score "${common[@]}" --group-by scenario --format latex
    run fx.tfpp.legacy score "${common[@]}" --profile b2d-legacy
    # The one telemetry file (route 1711, SimLingo step logs: not a metric_info.json layout).
    sim=$b2d/simlingo_bench2drive220_targetpoint_checkpoint.json
    run fx.simlingo.telemetry score --results "$sim" --routes "$xml" --telemetry "$b2d/telemetry"
    run fx.simlingo.telemetry-allow score --results "$sim" --routes "$xml" \
        --telemetry "$b2d/telemetry" --allow-missing-telemetry --maps "$maps" --format html
    run fx.simlingo.frames frames --results "$sim" --telemetry "$b2d/telemetry" --routes "$xml" \
        --route-id RouteScenario_1711_rep0
    # Duplicates: the raw shards together with the file merged from them.
    for d in error first last all; do
        run "fx.dup-$d" score --results "$b2d/tfpp_raw_shards" --results "$tfpp" --routes "$xml" \
            --allow-missing-telemetry --duplicates "$d"
    done
    # merge: the raw shards, each scored to a JSON part, merged into one report.
    parts=()
    for shard in "$b2d"/tfpp_raw_shards/eval_bench2drive220_*.json; do
        n=$(basename "$shard" .json)
        run "fx.part.$n" score --results "$shard" --routes "$xml" --allow-missing-telemetry \
            -o "$work/fx.part.$n.json"
        parts+=("$work/fx.part.$n.json")
    done
    for f in $formats; do
        run "fx.merge.$f" merge "${parts[@]}" --format "$f"
    done
    run fx.merge.rerun merge "${parts[@]}" --routes "$xml" --rerun-list "$work/out/fx.merge.rerun.txt" \
        --rerun-xml "$work/out/fx.merge.rerun.xml" --rerun-timeouts
    for f in json table markdown latex html; do
        run "fx.compare.$f" compare "tfpp=$tfpp" "pdm=$b2d/carla_garage_pdm_lite_b2d_traj_merged.json" \
            "uniad=$b2d/b2dzoo_UniAD-Base_merged.json" --routes "$xml" --allow-missing-telemetry \
            --format "$f"
    done
fi

rm -rf "$dest"
mkdir -p "$dest"
cp -r "$work/out/." "$dest/"
echo "output-identity: captured $(find "$dest" -type f | wc -l) files into $dest"
