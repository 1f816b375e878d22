#!/usr/bin/env bash
# Issue 34 finding 1 in a browser: the Markdown tables of `sds score` and `sds compare` over
# hostile scenario and run names (a <script>, a link, an image, bare URLs), rendered by a
# CommonMark renderer (the r3_01 test writes the HTML), then loaded in headless Chromium: the
# DOM the browser builds must hold no script, link or image. A control page, the same names
# rendered unescaped, must hold all three (else the check would check nothing).
# Called by scripts/html-report-test.sh; skips loudly without Chromium (scripts/browse.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
out=target/markdown-test
rm -rf "$out" && mkdir -p "$out/html"
# shellcheck source=browse.sh
source scripts/browse.sh
SDS_MARKDOWN_HTML_OUT="$(realpath "$out/html")" \
  cargo test -q -p sds-cli --release --test it r3_01_markdown_cells_render_as_their_text >/dev/null
pages=("$out"/html/*.html)
[ ${#pages[@]} -ge 3 ] || { echo "markdown browser test: expected the score, compare and control pages, found ${#pages[@]}" >&2; exit 1; }
for p in "${pages[@]}"; do
  browse "file://$(realpath "$p")" --dump-dom >"$out/dom-$(basename "$p")"
done
python3 - "$out" <<'PY'
import glob, os, sys
from html.parser import HTMLParser

class Count(HTMLParser):
    def __init__(self):
        super().__init__()
        self.tags = {"script": 0, "a": 0, "img": 0}
    def handle_starttag(self, tag, attrs):
        if tag in self.tags:
            self.tags[tag] += 1

out = sys.argv[1]
bad = []
for dom in sorted(glob.glob(os.path.join(out, "dom-*.html"))):
    c = Count()
    c.feed(open(dom, encoding="utf-8").read())
    name = os.path.basename(dom)[4:]
    if name == "control.html":
        if not all(c.tags.values()):
            bad.append(f"the control page has no live markup ({c.tags}): the check checks nothing")
        print(f"markdown browser test: control page (names unescaped): {c.tags}")
    else:
        if any(c.tags.values()):
            bad.append(f"{name}: live markup in the browser's DOM: {c.tags}")
        print(f"markdown browser test: {name}: no script, link or image")
if bad:
    print("\n".join(bad), file=sys.stderr)
    sys.exit(1)
print("markdown browser test: ok")
PY
