#!/usr/bin/env bash
# The HTML report, end to end: the demo scored as JSON and as HTML; the page parsed and every
# number compared with the JSON report (scripts/html_report_check.py), and a tampered copy must
# fail that check; then the page opened in headless Chromium: its script must run without a
# JavaScript error, lay out the waterfall and the per-route chart above the tables, and write
# its status and title after its self-checks, sorting and filtering
# are driven through the page's test hook (#test:...) and the resulting order compared with the
# JSON report's, and a PNG screenshot is taken. `sds compare --format html` opens the same way.
# Then the live page of a running `sds watch` (scripts/html-watch-test.sh), and the Markdown
# tables over hostile names as a browser builds them (scripts/markdown-browser-test.sh).
# Skips the browser part loudly (exit 0) only when Chromium is not installed and cannot be.
set -euo pipefail
cd "$(dirname "$0")/.."
target="${CARGO_TARGET_DIR:-target}"
out="$target/html-test"
rm -rf "$out" && mkdir -p "$out"
cargo build -q --release -p sds-cli --bin sds
sds="$target/release/sds"
"$sds" demo "$out/demo" 2>/dev/null
args=(--results "$out/demo/results.json" --telemetry "$out/demo/telemetry" --routes "$out/demo/routes.xml")
"$sds" score "${args[@]}" -o "$out/report.json"
"$sds" score "${args[@]}" --format html -o "$out/report.html"
# sds compare: each run's telemetry after its results (NAME=RESULTS:TELEMETRY); b is a with one
# route's score lowered, so the per-route deltas have an order to check.
python3 - "$out/demo/results.json" "$out/demo/results-b.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
# The last route with a score: unsorted it is not first, sorted by its delta it must be.
rec = [x for x in r["_checkpoint"]["records"] if x["scores"]["score_composed"] > 0][-1]
rec["scores"]["score_composed"] = rec["scores"]["score_composed"] / 2
json.dump(r, open(sys.argv[2], "w"))
PY
"$sds" compare "a=$out/demo/results.json:$out/demo/telemetry" "b=$out/demo/results-b.json:$out/demo/telemetry" \
  --routes "$out/demo/routes.xml" --format html -o "$out/compare.html"
"$sds" compare "a=$out/demo/results.json:$out/demo/telemetry" "b=$out/demo/results-b.json:$out/demo/telemetry" \
  --routes "$out/demo/routes.xml" --format json -o "$out/compare.json"

python3 scripts/html_report_check.py "$out/report.html" "$out/report.json"
# The check can fail: one number changed in the page must be caught.
python3 - "$out/report.html" "$out/tampered.html" <<'PY'
import re, sys
s = open(sys.argv[1], encoding="utf-8").read()
s, n = re.subn(r'(<td data-v=")([0-9.]+)(">)([0-9.]+)(</td>)', lambda m: m.group(1) + "12.5" + m.group(3) + "12.50" + m.group(5), s, count=1)
assert n == 1
open(sys.argv[2], "w", encoding="utf-8").write(s)
PY
if python3 scripts/html_report_check.py "$out/tampered.html" "$out/report.json" 2>/dev/null; then
  echo "html check: FAILED: a tampered page passed the check" >&2; exit 1
fi
# ... and so must a waterfall that draws another DS.
sed 's/<figure id="waterfall" data-ds="[0-9.]*"/<figure id="waterfall" data-ds="12.5"/' "$out/report.html" >"$out/tampered-waterfall.html"
if cmp -s "$out/report.html" "$out/tampered-waterfall.html" ||
   python3 scripts/html_report_check.py "$out/tampered-waterfall.html" "$out/report.json" 2>/dev/null; then
  echo "html check: FAILED: a page with a tampered waterfall passed the check" >&2; exit 1
fi
echo "html check: a tampered page is caught (a table cell, the waterfall's DS)"

# shellcheck source=browse.sh
source scripts/browse.sh
page="file://$(realpath "$out/report.html")"
browse "$page" --dump-dom >"$out/dom.html"
browse "$page#test:sort=ds_safe:desc" --dump-dom >"$out/dom-sorted.html"
browse "$page#test:filter=crash;sort=route:desc" --dump-dom >"$out/dom-filtered.html"
# The first route with a red light: its drill-down opened, its event markers measured.
red=$(python3 -c 'import json,sys; print(next(i for i,r in enumerate(json.load(open(sys.argv[1]))["routes"]) if any(e["kind"]=="red_light" and e["frame"] is not None for e in r["events"])))' "$out/report.json")
browse "$page#test:open=route-$red" --dump-dom >"$out/dom-open.html"
browse "file://$(realpath "$out/compare.html")" --dump-dom >"$out/dom-compare.html"
browse "file://$(realpath "$out/compare.html")#test:sort=dds:b:asc" --dump-dom >"$out/dom-compare-sorted.html"
browse "$page" --screenshot="$(realpath "$out")/report.png" --window-size=1280,2000 >/dev/null
browse "file://$(realpath "$out/compare.html")" --screenshot="$(realpath "$out")/compare.png" --window-size=1280,2400 >/dev/null

python3 - "$out" <<'PY'
import json, re, sys
out = sys.argv[1]
report = json.load(open(f"{out}/report.json"))
routes = report["routes"]
problems = []

def dom(name):
    return open(f"{out}/{name}", encoding="utf-8").read()

def status(d):
    m = re.search(r'<p id="status"[^>]*>([^<]*)</p>', d)
    return m.group(1) if m else None

def title(d):
    m = re.search(r"<title>([^<]*)</title>", d)
    return m.group(1) if m else None

def result(d):
    m = re.search(r'<pre id="test-result">([^<]*)</pre>', d)
    return None if m is None else [l for l in m.group(1).split("\n") if l]

for name in ("dom.html", "dom-sorted.html", "dom-filtered.html", "dom-open.html", "dom-compare.html", "dom-compare-sorted.html"):
    d = dom(name)
    if not (title(d) or "").endswith("[ready]") or not (status(d) or "").startswith("ok"):
        problems.append(f"{name}: title {title(d)!r}, status {status(d)!r}: the page's script did not finish")
d = dom("dom.html")
if f"ok: {len(routes)} routes" not in (status(d) or "") or "2 pictures" not in (status(d) or ""):
    problems.append(f"status {status(d)!r}")
# The waterfall and the route chart, laid out by the browser with a size (the page's script
# measured them), above the tables.
for pic in ("waterfall", "route-chart"):
    m = re.search(r'<figure id="%s"[^>]*data-rendered="(\d+)x(\d+)"' % pic, d)
    if not m or int(m.group(1)) < 200 or int(m.group(2)) < 100:
        problems.append(f"{pic}: not laid out ({m.group(0) if m else 'no data-rendered'})")
    elif d.index(f'<figure id="{pic}"') > d.index('id="tables"'):
        problems.append(f"{pic} is not above the tables")
for r in routes:
    if f'data-route="{r["route_id"]}"' not in d:
        problems.append(f"{r['route_id']} missing from the rendered page")
# The opened route's timeline: its red-light marker is drawn at the frame the JSON gives (the
# page's script measured the marker back to a frame), and so is every other placed event;
# a collision with a figure links to it.
d = dom("dom-open.html")
i, r = next((i, r) for i, r in enumerate(routes) if any(e["kind"] == "red_light" and e["frame"] is not None for e in r["events"]))
block = d[d.index(f'<details class="route" id="route-{i}"'):]
block = block[:block.index("</details>")]
markers = re.findall(r'<(?:circle|rect) class="ev ev-([a-z_]+)"[^>]*data-frame="(\d+)"[^>]*data-at-frame="(-?\d+)"', block)
placed = [e for e in r["events"] if e["frame"] is not None]
if len(markers) != len(placed):
    problems.append(f"route {i}: {len(markers)} measured markers for {len(placed)} placed events")
red = [e["frame"] for e in placed if e["kind"] == "red_light"]
red_drawn = [int(a) for k, f, a in markers if k == "red_light"]
if not red or red_drawn != red:
    problems.append(f"route {i}: red-light marker drawn at frame(s) {red_drawn}, the JSON gives {red}")
for k, f, a in markers:
    if k not in ("uncomfortable", "lateral_anomalous", "lateral_critical", "stationary") and abs(int(a) - int(f)) > 0:
        problems.append(f"route {i}: {k} marker at frame {a}, its data says {f}")
for href in re.findall(r'<a href="#(route-\d+-collision-\d+)">', d):
    if f'id="{href}"' not in d:
        problems.append(f"timeline link #{href} reaches no figure")
if not re.search(r'<a href="#route-\d+-collision-\d+">', d):
    problems.append("no timeline marker links to a collision figure")
cmp = json.load(open(f"{out}/compare.json"))
dc = dom("dom-compare.html")
for run in ("a", "b"):
    if f'<section id="run-{run}">' not in dc:
        problems.append(f"compare: run {run} missing")
if dc.count("<svg") < 1 or 'id="per-route"' not in dc:
    problems.append("compare: no forest plot or no per-route table")
# Every route key's links reach a row of each run.
for r in cmp["routes"]:
    for run, ids in zip(("a", "b"), r["route_ids"]):
        for rid in ids:
            if f'id="run-{run}-{rid}"' not in dc or f'href="#run-{run}-{rid}"' not in dc:
                problems.append(f"compare: no link or row for {run} {rid}")
# Sorted by b's DS delta ascending: the lowered route first, ties in the baseline's order.
keys = [r["key"] for r in cmp["routes"]]
dd = [r["values"][1][0] - r["values"][0][0] for r in cmp["routes"]]
want = [keys[i] for i in sorted(range(len(keys)), key=lambda i: (dd[i], i))]
got = result(dom("dom-compare-sorted.html"))
if got != want or dd[keys.index(want[0])] >= 0 or want[0] == keys[0]:
    problems.append(f"compare: sort by delta ds of b: {got} != {want}")

ids = [r["route_id"] for r in routes]
# Sorted by DS_safe, descending, ties in input order, empty last.
key = lambda i: (routes[i]["ds_safe"] is None, -(routes[i]["ds_safe"] or 0), i)
want = [ids[i] for i in sorted(range(len(ids)), key=key)]
got = result(dom("dom-sorted.html"))
if got != want:
    problems.append(f"sort by DS_safe: {got} != {want}")
# Filtered on "crash" (any cell), sorted by route id descending.
want = sorted([r["route_id"] for r in routes if "crash" in (r["scenario_type"] or "").lower()], reverse=True)
got = result(dom("dom-filtered.html"))
if got != want or not want:
    problems.append(f"filter 'crash': {got} != {want}")
if problems:
    for p in problems:
        print(f"browser test: {p}", file=sys.stderr)
    sys.exit(1)
print(f"browser test: ok: {len(routes)} routes rendered, status {status(dom('dom.html'))!r}; sort and filter as expected; route {i}'s red light drawn at frame {red_drawn[0]} as the JSON gives")
PY
# The state filter, with the state of the first route.
state=$(python3 -c 'import json,sys; print(str(json.load(open(sys.argv[1]))["routes"][0]["state"]).split(":")[0])' "$out/report.json")
browse "$page#test:state=$state" --dump-dom >"$out/dom-state.html"
n_state=$(python3 -c 'import json,sys; print(sum(1 for r in json.load(open(sys.argv[1]))["routes"] if str(r["state"]).split(":")[0]==sys.argv[2]))' "$out/report.json" "$state")
n_shown=$(sed -n '/<pre id="test-result">/,/<\/pre>/p' "$out/dom-state.html" | grep -c RouteScenario || true)
[ "$n_shown" = "$n_state" ] || { echo "browser test: state filter $state shows $n_shown routes, expected $n_state" >&2; exit 1; }
echo "browser test: state filter '$state' shows $n_shown route(s)"
python3 -c 'import sys; b=open(sys.argv[1],"rb").read(); assert b[:8]==b"\x89PNG\r\n\x1a\n" and len(b) > 20000, len(b); print(f"browser test: screenshot {sys.argv[1]} ({len(b)} bytes)")' "$out/report.png"

# A real 220-route run (long route ids and scenario names) at a 1440 px window: the routes table
# fits the page's 1400 px column (no sideways scrolling), and no status line shows.
fixtures=../shared/fixtures/b2d
if [ -f "$fixtures/carla_garage_tfpp_b2d_traj_merged.json" ]; then
  "$sds" score --results "$fixtures/carla_garage_tfpp_b2d_traj_merged.json" \
    --routes "$fixtures/routes/bench2drive220.xml" --allow-missing-telemetry --format html \
    -o "$out/real.html" 2>/dev/null
  browse "file://$(realpath "$out/real.html")" --window-size=1440,1000 --dump-dom >"$out/dom-real.html"
  python3 - "$out/dom-real.html" <<'PY'
import re, sys
d = open(sys.argv[1], encoding="utf-8").read()
m = re.search(r'<table id="routes"[^>]*data-width="(\d+)"[^>]*data-room="(\d+)"', d)
assert m, "the routes table has no measured width"
width, room = int(m.group(1)), int(m.group(2))
assert width <= room <= 1400, f"routes table {width} px wide in {room} px: it overflows"
assert re.search(r'<p id="status" hidden', d), "the status line is shown"
print(f"browser test: the 220-route table is {width} px wide in its {room} px")
PY
else
  echo "## browser test: $fixtures absent: the 220-route width check SKIPPED" >&2
fi

bash scripts/html-watch-test.sh
bash scripts/markdown-browser-test.sh
