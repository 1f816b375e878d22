#!/usr/bin/env bash
# install.sh PREFIX [--target TRIPLE]: builds the C library (release) and installs
#   PREFIX/include/sds_monitor.h
#   PREFIX/lib/libsds_monitor.a            (and libsds_monitor.so on the host)
#   PREFIX/lib/pkgconfig/sds_monitor.pc
# For a microcontroller: --target thumbv7em-none-eabihf (Cortex-M4F; static library only, built
# with fat LTO). Then: cc $(pkg-config --cflags sds_monitor) app.c $(pkg-config --libs --static sds_monitor)
# with PKG_CONFIG_PATH=PREFIX/lib/pkgconfig.
set -euo pipefail

usage() { echo "usage: bash bindings/c/install.sh PREFIX [--target TRIPLE]" >&2; exit 2; }
[ $# -ge 1 ] || usage
PREFIX=$1
shift
TARGET=""
while [ $# -gt 0 ]; do
  case $1 in
    --target) [ $# -ge 2 ] || usage; TARGET=$2; shift 2 ;;
    *) usage ;;
  esac
done
case $PREFIX in /*) ;; *) PREFIX="$(pwd)/$PREFIX" ;; esac

HERE="$(cd "$(dirname "$0")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
TARGET_DIR="${CARGO_TARGET_DIR:-$ROOT/target}"
VERSION=$(sed -n 's/^version = "\(.*\)"/\1/p' "$ROOT/Cargo.toml" | head -1)

if [ -z "$TARGET" ]; then
  (cd "$ROOT" && cargo build -q --release -p sds-capi)
  LIBDIR="$TARGET_DIR/release"
  LIBS=("$LIBDIR/libsds_monitor.a" "$LIBDIR/libsds_monitor.so")
  # What `rustc --print native-static-libs` reports for the staticlib on Linux (glibc).
  LIBS_PRIVATE="-lgcc_s -lutil -lrt -lpthread -lm -ldl -lc"
else
  # Bare metal: static only; fat LTO and one codegen unit make the smallest, fastest code.
  (cd "$ROOT" && CARGO_PROFILE_RELEASE_LTO=fat CARGO_PROFILE_RELEASE_CODEGEN_UNITS=1 \
    cargo rustc -q --release -p sds-capi --target "$TARGET" --crate-type staticlib)
  LIBDIR="$TARGET_DIR/$TARGET/release"
  LIBS=("$LIBDIR/libsds_monitor.a")
  LIBS_PRIVATE=""
fi

install -d "$PREFIX/include" "$PREFIX/lib/pkgconfig"
install -m 644 "$HERE/include/sds_monitor.h" "$PREFIX/include/"
for lib in "${LIBS[@]}"; do
  install -m 644 "$lib" "$PREFIX/lib/"
done
sed -e "s|@PREFIX@|$PREFIX|" -e "s|@VERSION@|$VERSION|" -e "s|@LIBS_PRIVATE@|$LIBS_PRIVATE|" \
  "$HERE/sds_monitor.pc.in" >"$PREFIX/lib/pkgconfig/sds_monitor.pc"
echo "installed sds_monitor $VERSION${TARGET:+ ($TARGET)} into $PREFIX"
