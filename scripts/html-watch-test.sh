#!/usr/bin/env bash
# The live HTML page of a running `sds watch` (docs/USAGE.md §8, issue #27), in headless Chromium.
# The demo run is played back: its checkpoint holds 4 of its 9 routes while `sds watch
# --format html -o live.html` runs. Checked from the DOM Chromium dumps:
# 1. the running page shows the partial report ("routes 9 (found 4)", 4 scored rows, 5 missing),
#    its script ran, and it carries the reload tag (<meta http-equiv="refresh">);
# 2. it reloads: served by scripts/html_watch_server.py, which records 2 more routes after the
#    first request and answers the next only once the watch has rewritten the page, the page
#    left open 6 s reloads (after its 1 s) and shows the 6 routes of the newer report, then
#    reloads again;
# 3. once the route set is complete the watch stops by itself, its final page is `sds score
#    --format html`'s byte for byte, carries no reload tag, and is requested once only within the same virtual-time budget.
# Called by html-report-test.sh; runs alone too. Skips loudly (exit 0) only without Chromium.
set -euo pipefail
cd "$(dirname "$0")/.."
target="${CARGO_TARGET_DIR:-target}"
out="$target/html-watch-test"
rm -rf "$out" && mkdir -p "$out"
cargo build -q --release -p sds-cli --bin sds
sds="$target/release/sds"
# shellcheck source=browse.sh
source scripts/browse.sh

"$sds" demo "$out/demo" 2>/dev/null
w="$out/watch"
mkdir -p "$w"
# The checkpoint after 4, 6 and 9 routes, as the evaluator writes it (progress [k, 9]).
python3 - "$out/demo/results.json" "$w" <<'PY'
import json, sys
src, w = sys.argv[1], sys.argv[2]
c = json.load(open(src))
records = c["_checkpoint"]["records"]
assert len(records) == 9, len(records)
for k, name in ((4, "results.json"), (6, "next.json"), (9, "full.json")):
    c["_checkpoint"]["records"] = records[:k]
    c["_checkpoint"]["progress"] = [k, len(records)]
    json.dump(c, open(f"{w}/{name}", "w"), indent=2)
PY
args=(--results "$w/results.json" --telemetry "$out/demo/telemetry" --routes "$out/demo/routes.xml")

watch_pid= server_pid=
cleanup() {
  [ -n "$server_pid" ] && kill "$server_pid" 2>/dev/null || true
  [ -n "$watch_pid" ] && kill "$watch_pid" 2>/dev/null || true
}
trap cleanup EXIT
fail() { echo "watch browser test: FAILED: $*" >&2; exit 1; }

# --interval 0.5: rounds every 0.5 s, the page's refresh every 1 s (whole seconds, rounded up).
"$sds" watch "${args[@]}" --format html -o "$w/live.html" --interval 0.5 --timeout 120 \
  --status-json 2>"$w/watch.log" &
watch_pid=$!
for _ in $(seq 200); do [ -s "$w/live.html" ] && break; sleep 0.1; done
[ -s "$w/live.html" ] || { cat "$w/watch.log" >&2; fail "no live.html after 20 s"; }

# Checks a dumped DOM: FILE FOUND RELOADS(yes|no) [WHAT]
check_dom() {
  python3 - "$@" <<'PY'
import re, sys
path, found, reloads = sys.argv[1], int(sys.argv[2]), sys.argv[3] == "yes"
d = open(path, encoding="utf-8").read()
problems = []
title = re.search(r"<title>([^<]*)</title>", d)
status = re.search(r'<p id="status"[^>]*>([^<]*)</p>', d)
if not (title and title.group(1).endswith("[ready]")) or not (status and status.group(1).startswith("ok")):
    problems.append(f"the page's script did not finish: title {title and title.group(1)!r}, status {status and status.group(1)!r}")
note = f"routes 9 (found {found})"
if not re.search(re.escape(note) + r"[,<]", d):
    problems.append(f"no {note!r} in the page: {re.findall(r'routes [0-9]+(?: [(]found [0-9]+[)])?', d)[:3]}")
rows = re.findall(r'<tr [^>]*data-route="([^"]+)" data-state="([^"]+)"', d)
states = {}
for route, state in rows:
    states.setdefault(route, state)
shown = sum(1 for s in states.values() if s != "missing")
if len(states) != 9 or shown != found:
    problems.append(f"the routes table has {len(states)} routes, {shown} with a record (expected 9, {found})")
refresh = re.findall(r'<meta http-equiv="refresh" content="(\d+)">', d)
if reloads and refresh != ["1"]:
    problems.append(f"a running watch's page must reload every 1 s: refresh tags {refresh}")
if not reloads and refresh:
    problems.append(f"the final page must not reload: refresh tags {refresh}")
if problems:
    for p in problems:
        print(f"watch browser test: {path}: {p}", file=sys.stderr)
    sys.exit(1)
print(f"watch browser test: {path.split('/')[-1]}: {note}, {shown} route rows with a record, "
      + ("reloads every 1 s" if reloads else "no reload tag"))
PY
}

# 1. The running page, from disk.
browse "file://$(realpath "$w/live.html")" --dump-dom >"$w/dom-live.html"
check_dom "$w/dom-live.html" 4 yes || fail "the running page"

# 2. A reload, seen by the server and in the DOM, within a virtual-time budget of 2.5 s (the budget
# lasts while the page keeps reloading): request 1 gets the page of 4 routes, the evaluator then
# records 2 more, request 2 (the reload, after 1 s) gets the watch's next page, request 3 (that
# page's own reload) is answered 204 No Content, so the DOM dumped is request 2's page.
rm -f "$w/port"
python3 scripts/html_watch_server.py "$w" --next "$w/next.json" --results "$w/results.json" \
  --expect "routes 9 (found 6)" --stop-after 2 &
server_pid=$!
for _ in $(seq 100); do [ -s "$w/port" ] && break; sleep 0.1; done
[ -s "$w/port" ] || fail "the page server did not start"
browse "http://127.0.0.1:$(cat "$w/port")/live.html" --virtual-time-budget=2500 --dump-dom >"$w/dom-reloaded.html"
kill "$server_pid" && wait "$server_pid" 2>/dev/null || true
server_pid=
echo "watch browser test: requests of the running page: $(head -3 "$w/requests.log" | tr '\n' ';')"
[ "$(sed -n 1p "$w/requests.log")" = "1 routes 9 (found 4) refresh" ] || fail "request 1: not the page of 4 routes"
[ "$(sed -n 2p "$w/requests.log")" = "2 routes 9 (found 6) refresh" ] || fail "the running page did not reload (or not to the newer report)"
[ "$(sed -n 3p "$w/requests.log")" = "3 stopped" ] || fail "the reloaded page did not reload again"
check_dom "$w/dom-reloaded.html" 6 yes || fail "after a reload the page does not show the newer report"

# 3. The route set complete: the watch stops by itself with the final report.
cp "$w/full.json" "$w/full.tmp" && cat "$w/full.tmp" >"$w/results.json"
code=0
for _ in $(seq 600); do kill -0 "$watch_pid" 2>/dev/null || break; sleep 0.1; done
if kill -0 "$watch_pid" 2>/dev/null; then cat "$w/watch.log" >&2; fail "the watch did not stop within 60 s of the set being complete"; fi
wait "$watch_pid" || code=$?
watch_pid=
grep -q "the route set is complete" "$w/watch.log" || { cat "$w/watch.log" >&2; fail "the watch stopped for another reason"; }
score_code=0
"$sds" score "${args[@]}" --format html -o "$w/score.html" 2>/dev/null || score_code=$?
[ "$code" = "$score_code" ] || fail "watch exit $code, sds score exit $score_code"
cmp -s "$w/live.html" "$w/score.html" || fail "the final page differs from sds score --format html"
rm -f "$w/port"
python3 scripts/html_watch_server.py "$w" --stop-after 1 &
server_pid=$!
for _ in $(seq 100); do [ -s "$w/port" ] && break; sleep 0.1; done
browse "http://127.0.0.1:$(cat "$w/port")/live.html" --virtual-time-budget=2500 --dump-dom >"$w/dom-final.html"
kill "$server_pid" && wait "$server_pid" 2>/dev/null || true
server_pid=
requests=$(wc -l <"$w/requests.log")
[ "$requests" = 1 ] || fail "the final page was requested $requests times within a virtual 2.5 s: it reloads"
check_dom "$w/dom-final.html" 9 no || fail "the final page"
echo "watch browser test: ok: the running page shows the partial table and reloads (4 -> 6 routes); the final page is sds score's and does not reload"
