# Sourced by the browser tests (html-report-test.sh, html-watch-test.sh): finds Chromium
# (installing it through scripts/setup.sh when it is absent; skips loudly, exit 0, when it cannot)
# into $chrome, and defines `browse URL FLAGS...`, which opens URL in headless Chromium with a
# fresh profile (the flags of the machine notes) and fails on a JavaScript error. Needs $out
# (where chromium.log goes).
chrome=$(command -v chromium || command -v chromium-browser || true)
if [ -z "$chrome" ]; then
  bash scripts/setup.sh >/dev/null 2>&1 || true
  chrome=$(command -v chromium || command -v chromium-browser || true)
fi
if [ -z "$chrome" ]; then
  # shellcheck source=skip.sh
  source scripts/skip.sh
  loud_skip html-report "chromium is not installed and scripts/setup.sh could not install it: the browser test was not run (by hand: apt-get install chromium)"
fi

# One fresh profile per run; the page's console goes to stderr (--enable-logging).
browse() { # browse URL WHAT... -> stdout of chromium; fails on a JavaScript error
  local url=$1; shift
  local profile; profile=$(mktemp -d)
  local log="$out/chromium.log"
  if ! timeout 120 "$chrome" --headless --no-sandbox --disable-gpu --disable-background-networking \
      --disable-component-update --no-first-run --user-data-dir="$profile" \
      --enable-logging=stderr --v=0 "$@" "$url" 2>"$log"; then
    rm -rf "$profile"; cat "$log" >&2; echo "browser test: chromium failed on $url" >&2; return 1
  fi
  rm -rf "$profile"
  if grep -E "Uncaught|CONSOLE.*(Error|error)" "$log" >&2; then
    echo "browser test: JavaScript error on $url" >&2; return 1
  fi
}
