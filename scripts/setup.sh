#!/usr/bin/env bash
# Installs what the test suite needs, idempotently: rustup components and thumb targets,
# QEMU (Debian bookworm-backports) and arm binutils. Safe to run again; prints what it did.
set -euo pipefail

log() { printf '[setup] %s\n' "$*" >&2; }

# Rust components and targets.
if command -v rustup >/dev/null 2>&1; then
  for c in rustfmt clippy; do
    rustup component list --installed 2>/dev/null | grep -q "^$c" || { log "adding $c"; rustup component add "$c"; }
  done
  for t in thumbv7m-none-eabi thumbv7em-none-eabihf; do
    rustup target list --installed | grep -qx "$t" || { log "adding target $t"; rustup target add "$t" || log "WARNING: could not add $t"; }
  done
fi

# cargo-fuzz for the fuzz smoke run (needs the nightly toolchain; skipped without it).
if cargo +nightly --version >/dev/null 2>&1 && ! cargo +nightly fuzz --version >/dev/null 2>&1; then
  log "installing cargo-fuzz"
  cargo install cargo-fuzz --locked >/dev/null 2>&1 || log "WARNING: cargo install cargo-fuzz failed"
fi

# apt packages: qemu-system-arm from bookworm-backports (bookworm's 7.2 would remove the
# preinstalled qemu-utils), binutils-arm-none-eabi for section sizes.
need_apt=()
command -v qemu-system-arm >/dev/null 2>&1 || need_apt+=(qemu-system-arm)
command -v arm-none-eabi-size >/dev/null 2>&1 || need_apt+=(binutils-arm-none-eabi)
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
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq $release "${need_apt[@]}" >/dev/null 2>&1 \
    || log "WARNING: apt-get install ${need_apt[*]} failed"
fi
# C API tests (bindings/c/run-tests.sh): arm-none-eabi-gcc links the Cortex-M4F C firmware (it
# uses GCC's own headers and libgcc only, so newlib, a recommendation, is not needed); valgrind
# and pkg-config for the host tests.
capi_apt=()
command -v arm-none-eabi-gcc >/dev/null 2>&1 || capi_apt+=(gcc-arm-none-eabi)
command -v valgrind >/dev/null 2>&1 || capi_apt+=(valgrind)
command -v pkg-config >/dev/null 2>&1 || capi_apt+=(pkg-config)
if [ ${#capi_apt[@]} -gt 0 ] && command -v apt-get >/dev/null 2>&1; then
  capi_sudo=""; [ "$(id -u)" -eq 0 ] || capi_sudo="sudo"
  log "installing ${capi_apt[*]} (C API tests)"
  $capi_sudo apt-get update -qq >/dev/null 2>&1 || true
  DEBIAN_FRONTEND=noninteractive $capi_sudo apt-get install -y -qq --no-install-recommends "${capi_apt[@]}" >/dev/null 2>&1 \
    || log "WARNING: apt-get install ${capi_apt[*]} failed"
fi
exit 0
