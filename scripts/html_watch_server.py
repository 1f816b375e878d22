"""A one-page HTTP server for the browser test of `sds watch`'s live page (html-watch-test.sh).

Serves DIR/live.html read from disk at every request and logs each request (one line: the
request number, the page's "routes N (found K)" note, and "refresh" when the page served carries
the reload tag) to DIR/requests.log; writes its port to DIR/port. With --next SRC --results DST
--expect TEXT: after answering the first request it rewrites DST in place with SRC's bytes (the
evaluator records more routes), and holds each later request until live.html contains TEXT (the
watch has rewritten the page), up to 60 s, so a page that reloads is answered with the newer
report whatever the timing. With --stop-after K, requests after the K-th are logged ("stopped") and
answered 204 No Content: the browser keeps showing the K-th page and its reloads end.

Usage: python3 html_watch_server.py DIR [--next SRC --results DST --expect TEXT] [--stop-after K]
"""

from __future__ import annotations

import argparse
import http.server
import re
import threading
import time
from pathlib import Path


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("dir", type=Path)
    ap.add_argument("--next", type=Path)
    ap.add_argument("--results", type=Path)
    ap.add_argument("--expect")
    ap.add_argument("--stop-after", type=int)
    a = ap.parse_args()
    page = a.dir / "live.html"
    log = a.dir / "requests.log"
    log.write_text("")
    lock = threading.Lock()
    count = [0]

    class Handler(http.server.BaseHTTPRequestHandler):
        def do_GET(self) -> None:  # noqa: N802 (the stdlib's name)
            if self.path.split("?")[0] != "/live.html":
                self.send_error(404)
                return
            with lock:
                count[0] += 1
                n = count[0]
            if a.stop_after is not None and n > a.stop_after:
                with lock, log.open("a") as f:
                    f.write(f"{n} stopped\n")
                self.send_response(204)
                self.end_headers()
                return
            if n > 1 and a.expect:
                until = time.monotonic() + 60
                while a.expect not in page.read_text(encoding="utf-8", errors="replace"):
                    if time.monotonic() > until:
                        break
                    time.sleep(0.05)
            body = page.read_bytes()
            note = re.search(rb"routes \d+( \(found \d+\))?", body)
            refresh = b'http-equiv="refresh"' in body
            with lock, log.open("a") as f:
                f.write(f"{n} {note.group(0).decode() if note else '-'}{' refresh' if refresh else ''}\n")
            self.send_response(200)
            self.send_header("Content-Type", "text/html; charset=utf-8")
            self.send_header("Content-Length", str(len(body)))
            self.send_header("Cache-Control", "no-store")
            self.end_headers()
            self.wfile.write(body)
            if n == 1 and a.next is not None and a.results is not None:
                # In place, not atomically, as the evaluator writes its checkpoint.
                with a.results.open("wb") as f:
                    f.write(a.next.read_bytes())

        def log_message(self, *args: object) -> None:
            pass

    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), Handler)
    (a.dir / "port").write_text(str(server.server_address[1]))
    server.serve_forever()


if __name__ == "__main__":
    main()
