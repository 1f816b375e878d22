#!/usr/bin/env bash
# Installs what scripts/test-all.sh uses, and nothing else, idempotently: rustfmt, clippy and the
# thumb targets; cargo-fuzz only beside an already installed nightly toolchain (the fuzz smoke run
# needs both and skips without them; nightly itself is never installed); qemu-system-arm >= 9
# (Debian bookworm-backports), arm binutils and gcc for the firmware tests; pinned Python tools
# (maturin, pytest, mypy, numpy) in a venv inside the build folder; Debian chromium for the HTML
# report's browser test. Safe to run again;
# prints one line for each thing it installs or skips.
set -euo pipefail

acted=""
log() { printf '[setup] %s\n' "$*" >&2; acted=1; }
# `cargo +nightly ...` would make rustup download a missing nightly unless auto-install is off.
export RUSTUP_AUTO_INSTALL=0

# Rust components and targets.
if command -v rustup >/dev/null 2>&1; then
  for c in rustfmt clippy; do
    rustup component list --installed 2>/dev/null | grep -q "^$c" || { log "adding $c"; rustup component add "$c"; }
  done
  for t in thumbv7m-none-eabi thumbv7em-none-eabihf; do
    rustup target list --installed | grep -qx "$t" || { log "adding target $t"; rustup target add "$t" || log "WARNING: could not add $t"; }
  done
fi

# cargo-fuzz for the fuzz smoke run, only when a nightly toolchain is installed (looked up in
# rustup's list: asking `cargo +nightly` could install one).
if ! rustup toolchain list 2>/dev/null | grep -q '^nightly'; then
  log "skipping cargo-fuzz: no nightly toolchain installed (the fuzz smoke run skips too)"
elif ! cargo +nightly fuzz --version >/dev/null 2>&1; then
  log "installing cargo-fuzz (nightly is installed: the fuzz smoke run uses it; takes minutes)"
  cargo install cargo-fuzz --locked >/dev/null 2>&1 || log "WARNING: cargo install cargo-fuzz failed"
fi

# apt packages: qemu-system-arm >= 9 from bookworm-backports (bookworm's 7.2 is too old for the
# insncount plugin's API and would remove the preinstalled qemu-utils), binutils-arm-none-eabi for
# section sizes, gcc to build the plugin;
need_apt=()
qemu_major=$(qemu-system-arm --version 2>/dev/null | sed -n '1s/.*version \([0-9]*\)\..*/\1/p')
[ "${qemu_major:-0}" -ge 9 ] || need_apt+=(qemu-system-arm)
command -v arm-none-eabi-size >/dev/null 2>&1 || need_apt+=(binutils-arm-none-eabi)
command -v gcc >/dev/null 2>&1 || need_apt+=(gcc)
# C API tests (bindings/c/run-tests.sh): arm-none-eabi-gcc links the Cortex-M4F C firmware (GCC's
# own headers and libgcc only: newlib, a recommendation, is not needed); valgrind and pkg-config
# for the host tests.
command -v arm-none-eabi-gcc >/dev/null 2>&1 || need_apt+=(gcc-arm-none-eabi)
command -v valgrind >/dev/null 2>&1 || need_apt+=(valgrind)
command -v pkg-config >/dev/null 2>&1 || need_apt+=(pkg-config)
# The HTML report's browser test (scripts/html-report-test.sh): headless Chromium.
command -v chromium >/dev/null 2>&1 || command -v chromium-browser >/dev/null 2>&1 || need_apt+=(chromium)
if [ ${#need_apt[@]} -gt 0 ] && command -v apt-get >/dev/null 2>&1; then
  SUDO=""; [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  if grep -qs bookworm /etc/os-release && ! grep -rqs bookworm-backports /etc/apt/sources.list /etc/apt/sources.list.d/; then
    log "enabling bookworm-backports"
    printf 'Types: deb\nURIs: http://deb.debian.org/debian\nSuites: bookworm-backports\nComponents: main\nSigned-By: /usr/share/keyrings/debian-archive-keyring.gpg\n' \
      | $SUDO tee /etc/apt/sources.list.d/bookworm-backports.sources >/dev/null
  fi
  log "installing ${need_apt[*]}"
  $SUDO apt-get update -qq >/dev/null 2>&1 || true
  release=""; grep -qs bookworm /etc/os-release && release="-t bookworm-backports"
  # shellcheck disable=SC2086
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends $release "${need_apt[@]}" >/dev/null 2>&1 \
    || log "WARNING: apt-get install ${need_apt[*]} failed"
fi
# Python tools for bindings/python/run-tests.sh, pinned, in a venv inside the build folder:
# maturin builds the wheel; the test requirements and maturin (pip's build backend when it
# installs the source distribution) are downloaded once into a local wheelhouse so each test run
# installs into a fresh venv without the network. Without PyPI the Python tests
# skip, loudly.
py_target="${CARGO_TARGET_DIR:-$(cd "$(dirname "$0")/.." && pwd)/target}"
py_tools="$py_target/py-tools"
py_pins="maturin==1.16.0 pytest==9.2.0 mypy==2.4.1 numpy==2.4.6"
if ! command -v python3 >/dev/null 2>&1; then
  log "WARNING: no python3: the Python package tests will skip"
elif [ "$(cat "$py_tools/pins" 2>/dev/null)" != "$py_pins" ] || ! ls "$py_tools"/wheelhouse/maturin-*.whl >/dev/null 2>&1; then
  log "installing $py_pins into $py_tools (venv) and its wheelhouse"
  rm -rf "$py_tools"
  # shellcheck disable=SC2086
  if python3 -m venv "$py_tools" \
    && "$py_tools/bin/pip" install -q $py_pins \
    && "$py_tools/bin/pip" download -q -d "$py_tools/wheelhouse" $py_pins; then
    echo "$py_pins" > "$py_tools/pins"
  else
    log "WARNING: could not install the Python tools (is PyPI reachable?): the Python package tests will skip"
  fi
fi

[ -n "$acted" ] || log "everything the tests use is installed"
exit 0
