#!/usr/bin/env bash
# Builds monitor-core for the thumb targets, with and without defmt.
set -euo pipefail
cd "$(dirname "$0")/.."
for t in thumbv7em-none-eabihf thumbv7m-none-eabi; do
  if rustup target list --installed 2>/dev/null | grep -qx "$t"; then
    cargo build -q -p monitor-core --release --target "$t"
    cargo build -q -p monitor-core --release --target "$t" --features defmt
    echo "monitor-core builds for $t (with and without defmt)"
  else
    echo "WARNING: target $t not installed; skipped" >&2
  fi
done
