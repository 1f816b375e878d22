"""Memory of `sds watch` over a 220-route playback (issue 27: "memory stays flat"). A benchmark,
not a test: it prints numbers (docs/PERFORMANCE.md records them) and fails only when the watch
does not behave (an error, a round that never comes, no final report).

The large demo (`sds demo --large`: 220 routes) is played back into a fresh run folder in
STEPS steps: each step copies the telemetry of the routes that ended (fresh files, as the
evaluator writes them) and rewrites the checkpoint in place. `sds watch` runs over it under
`/usr/bin/time -v`; its resident memory (VmRSS of /proc/PID/status) is sampled every 20 ms.
Before the last step the watch idles IDLE rounds over the same files, the checkpoint rewritten
unchanged (same bytes, new modification time) every other round: memory must not grow with
rounds. Then the last routes end and the watch stops by itself (the route set is complete).

Usage: python3 scripts/watch_memory_bench.py SDS_BIN WORKDIR [--frames 4000] [--steps 10]
       [--interval 0.5] [--idle 20]
"""

from __future__ import annotations

import argparse
import json
import re
import shutil
import subprocess
import sys
import threading
import time
from pathlib import Path
from typing import Any, Dict, List, Optional, Tuple


def rss_kb(pid: int) -> Optional[Tuple[int, int]]:
    """(VmRSS, VmHWM) in kB, or None once the process is gone."""
    try:
        text = Path(f"/proc/{pid}/status").read_text()
    except OSError:
        return None
    rss = re.search(r"VmRSS:\s+(\d+) kB", text)
    hwm = re.search(r"VmHWM:\s+(\d+) kB", text)
    if not rss or not hwm:
        return None
    return int(rss.group(1)), int(hwm.group(1))


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("sds", type=Path)
    ap.add_argument("workdir", type=Path)
    ap.add_argument("--frames", type=int, default=4000)
    ap.add_argument("--steps", type=int, default=10)
    ap.add_argument("--interval", type=float, default=0.5)
    ap.add_argument("--idle", type=int, default=20)
    a = ap.parse_args()
    sds = a.sds.resolve()
    src, run = a.workdir / "src", a.workdir / "run"
    shutil.rmtree(a.workdir, ignore_errors=True)
    subprocess.run([str(sds), "demo", "--large", "--large-frames", str(a.frames), str(src)],
                   check=True, capture_output=True)
    checkpoint: Dict[str, Any] = json.loads((src / "results.json").read_text())
    records: List[Dict[str, Any]] = checkpoint["_checkpoint"]["records"]
    n = len(records)
    (run / "telemetry").mkdir(parents=True)
    results = run / "results.json"

    def reveal(k: int) -> None:
        for r in records[:k]:
            dst = run / "telemetry" / r["save_name"]
            if not dst.exists():
                shutil.copytree(src / "telemetry" / r["save_name"], dst)
        c = dict(checkpoint)
        c["_checkpoint"] = dict(checkpoint["_checkpoint"], records=records[:k], progress=[k, n])
        with open(results, "w") as f:  # in place, not atomically
            json.dump(c, f, indent=2)

    def rewrite_same() -> None:
        data = results.read_bytes()
        with open(results, "wb") as f:
            f.write(data)

    steps = [round(n * (i + 1) / a.steps) for i in range(a.steps)]
    reveal(steps[0])
    err_path, time_path = run / "watch.log", run / "time.txt"
    err = open(err_path, "w")
    cmd = ["/usr/bin/time", "-v", "-o", str(time_path), str(sds), "watch",
           "--results", str(results), "--telemetry", str(run / "telemetry"),
           "--routes", str(src / "routes.xml"), "--maps", str(src / "maps"),
           "-o", str(run / "live.json"), "--status-json", "--interval", str(a.interval),
           "--timeout", "900"]
    timer = subprocess.Popen(cmd, stderr=err)
    pid = None
    for _ in range(200):
        kids = Path(f"/proc/{timer.pid}/task/{timer.pid}/children").read_text().split()
        if kids:
            pid = int(kids[0])
            break
        time.sleep(0.01)
    if pid is None:
        print("watch bench: sds watch did not start", file=sys.stderr)
        return 1
    samples: List[Tuple[float, int]] = []
    hwm = [0]
    stop = threading.Event()

    def sample() -> None:
        while not stop.is_set():
            s = rss_kb(pid)
            if s is None:
                return
            samples.append((time.monotonic(), s[0]))
            hwm[0] = max(hwm[0], s[1])
            time.sleep(0.02)

    threading.Thread(target=sample, daemon=True).start()

    def rounds() -> List[Dict[str, Any]]:
        out = []
        for line in err_path.read_text().splitlines():
            try:
                v = json.loads(line)
            except ValueError:
                continue
            if isinstance(v, dict) and "round" in v:
                out.append(v)
        return out

    def wait_round(pred: Any, limit: float = 120) -> Dict[str, Any]:
        until = time.monotonic() + limit
        seen = len(rounds())
        while time.monotonic() < until:
            rs = rounds()
            for r in rs[seen:]:
                if pred(r):
                    return r
            if timer.poll() is not None:
                break
            time.sleep(0.02)
        raise SystemExit(f"watch bench: no expected round (log {err_path})")

    def window(t0: float) -> List[int]:
        return [kb for t, kb in samples if t >= t0]

    rows = []
    for i, k in enumerate(steps[:-1]):
        t0 = time.monotonic()
        if i > 0:
            reveal(k)
        r = wait_round(lambda r: r.get("done") == k and r.get("rescored") == 0)  # settled
        w = window(t0)
        rows.append((i + 1, k, r["round"], max(w) / 1024, w[-1] / 1024, r["round_ms"]))
    # Idle rounds over the same files (the checkpoint re-saved unchanged every other round).
    t0 = time.monotonic()
    idle = []
    for j in range(a.idle):
        if j % 2 == 0:
            rewrite_same()
        r = wait_round(lambda r: "done" in r)
        idle.append(r)
    w = window(t0)
    idle_rss = (min(w) / 1024, max(w) / 1024, w[0] / 1024, w[-1] / 1024)
    # The last routes: complete, the watch stops.
    t0 = time.monotonic()
    reveal(steps[-1])
    code = timer.wait(timeout=300)
    stop.set()
    err.close()
    w = window(t0)
    rows.append((len(steps), steps[-1], rounds()[-1]["round"], max(w) / 1024 if w else float("nan"),
                 w[-1] / 1024 if w else float("nan"), rounds()[-1]["round_ms"]))
    log = err_path.read_text()
    if "the route set is complete" not in log:
        print(log[-2000:], file=sys.stderr)
        print("watch bench: the watch did not stop on the complete set", file=sys.stderr)
        return 1
    peak = re.search(r"Maximum resident set size \(kbytes\): (\d+)", time_path.read_text())
    print(f"frames per route {a.frames}, {n} routes in {a.steps} steps, interval {a.interval} s; "
          f"watch exit {code}")
    print("| step | routes done | round | max RSS in step | RSS at step end | round time |")
    print("|---|---|---|---|---|---|")
    for s, k, rnd, mx, end, ms in rows:
        print(f"| {s} | {k} | {rnd} | {mx:.1f} MB | {end:.1f} MB | {ms:.1f} ms |")
    print(f"idle: {a.idle} rounds at {steps[-2]} routes (checkpoint re-saved unchanged every other "
          f"round; rescored {sum(r['rescored'] for r in idle)}): RSS {idle_rss[2]:.1f} MB at the "
          f"start, {idle_rss[3]:.1f} MB at the end, range {idle_rss[0]:.1f}-{idle_rss[1]:.1f} MB; "
          f"round time median {sorted(r['round_ms'] for r in idle)[len(idle) // 2]:.1f} ms")
    print(f"peak RSS: {int(peak.group(1)) / 1024 if peak else float('nan'):.1f} MB (/usr/bin/time -v), "
          f"VmHWM {hwm[0] / 1024:.1f} MB; samples {len(samples)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
