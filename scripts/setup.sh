#!/usr/bin/env bash
# Installs what scripts/test-all.sh uses, and nothing else, idempotently: rustfmt, clippy and the
# thumb targets (rustup); cargo-fuzz only beside an already installed nightly toolchain (the fuzz
# smoke run needs both and skips without them; nightly itself is never installed);
# qemu-system-arm >= 9 (Debian bookworm-backports), the ARM binutils and gcc, valgrind,
# pkg-config, gcc/g++ and Chromium (apt); pinned Python tools (maturin, pytest, mypy, numpy, pandas) in a
# venv inside the build folder, and the data packages the Python tests use where they install
# (pyarrow, duckdb, wandb, tensorboard, mlflow-skinny: downloaded into its wheelhouse; without
# them only the Parquet, DuckDB and tracker tests skip).
#
# Works from nothing: every probe of a tool that may be absent is safe under `set -e`; each step
# prints one line saying what it installs or skips; an install that fails names the package and
# the command to run by hand, and setup still exits 0: the test steps that need what is missing
# skip loudly (and test-all.sh lists them at the end). scripts/setup-test.sh proves this in a
# sandbox PATH with stub package managers.
#
# Environment (for that test; users leave them unset): SDS_SETUP_OS_RELEASE (default
# /etc/os-release) and SDS_SETUP_APT_DIR (default /etc/apt).
set -euo pipefail

os_release="${SDS_SETUP_OS_RELEASE:-/etc/os-release}"
apt_dir="${SDS_SETUP_APT_DIR:-/etc/apt}"

missing=() # "what is missing -- how to install it by hand -- what skips without it"
log() { printf '[setup] %s\n' "$*" >&2; }
have() { command -v "$1" >/dev/null 2>&1; }
lacks() { missing+=("$1"); }
# `cargo +nightly ...` would make rustup download a missing nightly unless auto-install is off.
export RUSTUP_AUTO_INSTALL=0

# --- Rust components and targets (rustup) ----------------------------------------------------
rust_targets="thumbv7m-none-eabi thumbv7em-none-eabihf"
if have rustup; then
  for c in rustfmt clippy; do
    if ! { rustup component list --installed 2>/dev/null || true; } | grep -q "^$c"; then
      log "adding the rust component $c (rustup component add $c)"
      rustup component add "$c" >/dev/null 2>&1 \
        || lacks "rust component $c -- rustup component add $c -- cargo fmt / cargo clippy fail"
    fi
  done
  for t in $rust_targets; do
    if ! { rustup target list --installed 2>/dev/null || true; } | grep -qx "$t"; then
      log "adding the rust target $t (rustup target add $t)"
      rustup target add "$t" >/dev/null 2>&1 \
        || lacks "rust target $t -- rustup target add $t -- the no_std, firmware and C firmware tests skip"
    fi
  done
else
  sysroot=$({ rustc --print sysroot 2>/dev/null || true; })
  for t in $rust_targets; do
    if [ -z "$sysroot" ] || [ ! -d "$sysroot/lib/rustlib/$t/lib" ]; then
      lacks "rust target $t (no rustup to add it) -- install the target for your toolchain -- the no_std, firmware and C firmware tests skip"
    fi
  done
fi

# cargo-fuzz for the fuzz smoke run, only when a nightly toolchain is installed (looked up in
# rustup's list: asking `cargo +nightly` could install one).
if ! { rustup toolchain list 2>/dev/null || true; } | grep -q '^nightly'; then
  log "skipping cargo-fuzz: no nightly toolchain installed (the fuzz smoke run skips too)"
elif ! cargo +nightly fuzz --version >/dev/null 2>&1; then
  log "installing cargo-fuzz (cargo install cargo-fuzz --locked; nightly is installed; takes minutes)"
  cargo install cargo-fuzz --locked >/dev/null 2>&1 \
    || lacks "cargo-fuzz -- cargo install cargo-fuzz --locked -- the fuzz smoke run skips"
fi

# --- Debian packages (apt) -------------------------------------------------------------------
# qemu-system-arm >= 9 from bookworm-backports (bookworm's 7.2 is too old for the insncount
# plugin's API and would remove the preinstalled qemu-utils); the ARM binutils for section sizes
# and gcc-arm-none-eabi for the C firmware (GCC's own headers and libgcc: newlib is not needed);
# gcc for the QEMU plugin, g++ for the C++ test, valgrind and pkg-config for the C API tests;
# Chromium for the HTML report's browser test.
qemu_major() {
  have qemu-system-arm || { echo 0; return; }
  { qemu-system-arm --version 2>/dev/null || true; } | sed -n '1s/.*version \([0-9]*\)\..*/\1/p'
}
# Is the Debian package's tool there? (one probe per package)
present() {
  case "$1" in
    qemu-system-arm) [ "$(qemu_major)" -ge 9 ] 2>/dev/null ;;
    binutils-arm-none-eabi) have arm-none-eabi-size && have arm-none-eabi-objdump ;;
    gcc-arm-none-eabi) have arm-none-eabi-gcc ;;
    gcc) have gcc ;;
    g++) have g++ ;;
    valgrind) have valgrind ;;
    pkg-config) have pkg-config ;;
    chromium) have chromium || have chromium-browser ;;
  esac
}
# What skips without each package.
needed_by() {
  case "$1" in
    qemu-system-arm) echo "the firmware and C firmware tests under QEMU skip" ;;
    binutils-arm-none-eabi | gcc-arm-none-eabi) echo "the no_std image check, the firmware and C firmware tests skip" ;;
    gcc | g++ | valgrind | pkg-config) echo "the C API tests skip" ;;
    chromium) echo "the browser test of the HTML report skips" ;;
  esac
}
apt_packages="qemu-system-arm binutils-arm-none-eabi gcc-arm-none-eabi gcc g++ valgrind pkg-config chromium"
need_apt=()
for p in $apt_packages; do present "$p" || need_apt+=("$p"); done

bookworm=""
grep -qs bookworm "$os_release" && bookworm=1
release_opt=""
[ -n "$bookworm" ] && release_opt="-t bookworm-backports"
by_hand="apt-get install --no-install-recommends $release_opt"
if [ ${#need_apt[@]} -eq 0 ]; then
  :
elif ! have apt-get; then
  log "cannot install ${need_apt[*]}: no apt-get on this machine"
else
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then
    if have sudo; then SUDO="sudo"; else log "cannot install ${need_apt[*]}: not root and no sudo"; need_apt=(); fi
    by_hand="sudo $by_hand"
  fi
  if [ ${#need_apt[@]} -gt 0 ]; then
    if [ -n "$bookworm" ] && ! grep -rqs bookworm-backports "$apt_dir/sources.list" "$apt_dir/sources.list.d/"; then
      log "enabling bookworm-backports ($apt_dir/sources.list.d/bookworm-backports.sources)"
      printf 'Types: deb\nURIs: http://deb.debian.org/debian\nSuites: bookworm-backports\nComponents: main\nSigned-By: /usr/share/keyrings/debian-archive-keyring.gpg\n' \
        | $SUDO tee "$apt_dir/sources.list.d/bookworm-backports.sources" >/dev/null \
        || log "WARNING: could not write $apt_dir/sources.list.d/bookworm-backports.sources"
    fi
    log "installing ${need_apt[*]} (apt-get)"
    $SUDO apt-get update -qq >/dev/null 2>&1 || log "WARNING: apt-get update failed"
    # shellcheck disable=SC2086
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends $release_opt "${need_apt[@]}" >/dev/null 2>&1 \
      || log "WARNING: apt-get install ${need_apt[*]} failed"
  fi
fi
# Whatever is still absent after the install is named, with the command that installs it.
for p in $apt_packages; do
  present "$p" || lacks "Debian package $p -- $by_hand $p -- $(needed_by "$p")"
done

# --- Python tools (pip, in a venv inside the build folder) -----------------------------------
# maturin builds the wheel; the test requirements and maturin (pip's build backend when it
# installs the source distribution) are downloaded once into a local wheelhouse so each test run
# installs into a fresh venv without the network.
py_target="${CARGO_TARGET_DIR:-$(cd "$(dirname "$0")/.." && pwd)/target}"
py_tools="$py_target/py-tools"
py_pins="maturin==1.16.0 pytest==9.2.0 mypy==2.4.1 numpy==2.4.6 pandas==3.1.1 mcap==1.6.0 mcap-ros2-support==0.6.0"
# Ray drives the scale-out test (one task per shard, docs/SCORE.md §13.2); it has no wheel for some
# platforms and Pythons, so it is pinned apart: without it only that test skips, loudly.
py_ray_pin="ray==2.60.0"
py_by_hand="python3 -m venv $py_tools && $py_tools/bin/pip install $py_pins && $py_tools/bin/pip download -d $py_tools/wheelhouse $py_pins"
if ! have python3; then
  lacks "python3 -- apt-get install python3 python3-venv -- the Python package tests and the map cross-check skip"
elif [ "$(cat "$py_tools/pins" 2>/dev/null || true)" != "$py_pins $py_ray_pin" ] || ! ls "$py_tools"/wheelhouse/maturin-*.whl >/dev/null 2>&1; then
  log "installing $py_pins into $py_tools (a venv) and its wheelhouse (pip)"
  rm -rf "$py_tools"
  # shellcheck disable=SC2086
  if python3 -m venv "$py_tools" >/dev/null 2>&1 \
    && "$py_tools/bin/pip" install -q $py_pins >/dev/null 2>&1 \
    && "$py_tools/bin/pip" download -q -d "$py_tools/wheelhouse" $py_pins >/dev/null 2>&1; then
    # Ray (and its dependencies) into the wheelhouse only: the test venv installs it offline.
    "$py_tools/bin/pip" download -q -d "$py_tools/wheelhouse" $py_ray_pin >/dev/null 2>&1 \
      || lacks "$py_ray_pin -- $py_tools/bin/pip download -d $py_tools/wheelhouse $py_ray_pin (no wheel for this platform or Python?) -- the Ray scale-out test skips"
    echo "$py_pins $py_ray_pin" > "$py_tools/pins"
  else
    lacks "Python tools ($py_pins) -- $py_by_hand (needs PyPI and python3-venv) -- the Python package tests skip"
  fi
fi

# The data packages (Parquet, DuckDB, the trackers): a group of their own, so that one that does
# not install skips only its tests. Downloaded into the wheelhouse (run-tests.sh installs them
# into its fresh venv, offline), resolved with numpy and pandas at their pins.
py_data_pins="pyarrow==26.0.1 duckdb==2.0.1 wandb==0.31.0 tensorboard==2.21.0 mlflow-skinny==3.17.2"
if [ -x "$py_tools/bin/pip" ] && [ -f "$py_tools/pins" ] \
  && [ "$(cat "$py_tools/data-pins" 2>/dev/null || true)" != "$py_data_pins" ]; then
  log "downloading $py_data_pins into $py_tools/wheelhouse (pip)"
  # shellcheck disable=SC2086
  if "$py_tools/bin/pip" download -q -d "$py_tools/wheelhouse" numpy==2.4.6 pandas==3.1.1 $py_data_pins >/dev/null 2>&1; then
    echo "$py_data_pins" > "$py_tools/data-pins"
  else
    lacks "Python data packages ($py_data_pins) -- $py_tools/bin/pip download -d $py_tools/wheelhouse numpy==2.4.6 pandas==3.1.1 $py_data_pins -- the Parquet, DuckDB and tracker tests of the Python package skip"
  fi
fi

# --- what is missing ---------------------------------------------------------------------------
if [ ${#missing[@]} -gt 0 ]; then
  printf '[setup] ########################################################################\n' >&2
  printf '[setup] NOT INSTALLED (%d); the tests that need them skip, loudly:\n' "${#missing[@]}" >&2
  for m in "${missing[@]}"; do
    what=${m%% -- *}; rest=${m#* -- }; how=${rest%% -- *}; why=${rest#* -- }
    printf '[setup]   %s\n[setup]       install by hand: %s\n[setup]       without it: %s\n' "$what" "$how" "$why" >&2
  done
  printf '[setup] ########################################################################\n' >&2
else
  log "everything the tests use is installed"
fi
exit 0
