#!/usr/bin/env bash
# Proves scripts/setup.sh works from nothing, without installing anything: setup runs in a
# sandbox PATH from which the optional tools (qemu-system-arm, arm-none-eabi-*, chromium,
# valgrind, pkg-config, g++, maturin, ...) are hidden, with apt-get, rustup, python3 (venv + pip)
# and sudo replaced by stubs that record their arguments. Three cases:
#   1. stubs that succeed (and "install" stand-ins): setup exits 0 and asks for exactly the
#      missing packages, components, targets and Python tools; run again, it installs nothing;
#   2. stubs that fail: setup still exits 0 and names every missing package with the command that
#      installs it by hand;
#   3. no package manager at all (no apt-get, no rustup, no python3): exit 0, everything named.
# Usage: bash scripts/setup-test.sh [SETUP_SCRIPT] (default: scripts/setup.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
setup="$(pwd)/${1:-scripts/setup.sh}"
[ -f "$setup" ] || { echo "setup-test: no $setup" >&2; exit 2; }

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fails=0
check() { # check DESCRIPTION COMMAND...
  local what=$1; shift
  if "$@"; then echo "  ok: $what"; else echo "  FAILED: $what" >&2; fails=$((fails + 1)); fi
}

# The base tools every Debian machine has (and setup may use); nothing optional.
base_tools="bash sh env cat sed grep id tee ls rm mkdir dirname basename head tail tr sort cut wc printf touch chmod ln cp mv mktemp date uname"

make_sandbox() { # make_sandbox DIR MODE(ok|fail|none)
  local dir=$1 mode=$2
  mkdir -p "$dir/bin" "$dir/log" "$dir/etc/apt/sources.list.d" "$dir/target" "$dir/home"
  for t in $base_tools; do
    local p; p=$(command -v "$t" 2>/dev/null || true)
    [ -n "$p" ] && [ "${p#/}" != "$p" ] && ln -sf "$p" "$dir/bin/$t"
  done
  # gcc is on every fresh machine of this kind; the rest of the apt list is not.
  ln -sf "$(command -v gcc)" "$dir/bin/gcc"
  printf 'PRETTY_NAME="Debian GNU/Linux 12 (bookworm)"\nVERSION_CODENAME=bookworm\n' >"$dir/etc/os-release"
  [ "$mode" = none ] && return 0
  local status=0
  [ "$mode" = fail ] && status=1

  # apt-get: records its arguments; `install` puts stand-in tools on PATH (unless failing).
  cat >"$dir/bin/apt-get" <<EOF
#!$(command -v bash)
echo "apt-get \$*" >>"$dir/log/calls"
[ $status -eq 0 ] || exit 100
if [ "\$1" = install ] || [[ " \$* " == *" install "* ]]; then
  for a in "\$@"; do
    case "\$a" in
      qemu-system-arm) tools="qemu-system-arm" ;;
      binutils-arm-none-eabi) tools="arm-none-eabi-size arm-none-eabi-nm arm-none-eabi-objdump" ;;
      gcc-arm-none-eabi) tools="arm-none-eabi-gcc" ;;
      g++|valgrind|pkg-config|chromium) tools="\$a" ;;
      *) tools="" ;;
    esac
    for t in \$tools; do
      printf '#!/bin/sh\necho "QEMU emulator version 10.0.2 (stand-in \$t)"\n' >"$dir/bin/\$t"
      chmod +x "$dir/bin/\$t"
    done
  done
fi
exit 0
EOF
  # rustup: nothing installed, stable only; add records.
  cat >"$dir/bin/rustup" <<EOF
#!$(command -v bash)
echo "rustup \$*" >>"$dir/log/calls"
case "\$1 \$2" in
  "toolchain list") echo "stable-x86_64-unknown-linux-gnu (default)" ;;
  "component list"|"target list") [ -f "$dir/log/rustup-added" ] && cat "$dir/log/rustup-added" ;;
  "component add"|"target add") [ $status -eq 0 ] || exit 1; echo "\$3" >>"$dir/log/rustup-added" ;;
esac
exit 0
EOF
  # python3: `-m venv DIR` makes a venv whose pip records and fakes the wheelhouse.
  cat >"$dir/bin/python3" <<EOF
#!$(command -v bash)
echo "python3 \$*" >>"$dir/log/calls"
[ $status -eq 0 ] || exit 1
if [ "\$1 \$2" = "-m venv" ]; then
  mkdir -p "\$3/bin"
  cat >"\$3/bin/pip" <<'PIP'
#!$(command -v bash)
echo "pip \$*" >>"$dir/log/calls"
if [ "\$1" = download ]; then
  while [ \$# -gt 0 ]; do [ "\$1" = -d ] && { mkdir -p "\$2"; touch "\$2/maturin-1.16.0-py3-none-any.whl"; }; shift; done
fi
exit 0
PIP
  chmod +x "\$3/bin/pip"
fi
exit 0
EOF
  # sudo (when the test runs as a user): runs the command.
  printf '#!%s\n"$@"\n' "$(command -v bash)" >"$dir/bin/sudo"
  chmod +x "$dir/bin/"*
}

run_setup() { # run_setup DIR -> status; stderr in DIR/log/stderr
  local dir=$1
  env -i PATH="$dir/bin" HOME="$dir/home" CARGO_TARGET_DIR="$dir/target" \
    SDS_SETUP_OS_RELEASE="$dir/etc/os-release" SDS_SETUP_APT_DIR="$dir/etc/apt" \
    "$(command -v bash)" "$setup" >"$dir/log/stdout" 2>"$dir/log/stderr"
}
calls() { cat "$1/log/calls" 2>/dev/null || true; }
apt_install_line() { calls "$1" | grep '^apt-get .*install' || true; }
packages_asked() { # the packages of the install line, sorted
  apt_install_line "$1" | tr ' ' '\n' | grep -v '^-' | grep -vx 'apt-get\|install\|bookworm-backports' | sort | tr '\n' ' '
}
expected="binutils-arm-none-eabi chromium g++ gcc-arm-none-eabi pkg-config qemu-system-arm valgrind "

echo "case 1: stubs that succeed"
s="$work/ok"
make_sandbox "$s" ok
status=0; run_setup "$s" || status=$?
check "setup exits 0 (got $status; stderr: $(tail -3 "$s/log/stderr" | tr '\n' ' '))" [ "$status" -eq 0 ]
check "apt-get installs exactly the missing packages (asked: $(packages_asked "$s"))" [ "$(packages_asked "$s")" = "$expected" ]
check "from bookworm-backports" grep -q -- '-t bookworm-backports' <<<"$(apt_install_line "$s")"
check "bookworm-backports enabled inside the sandbox" grep -q bookworm-backports "$s/etc/apt/sources.list.d/bookworm-backports.sources"
for want in "rustup component add rustfmt" "rustup component add clippy" \
            "rustup target add thumbv7m-none-eabi" "rustup target add thumbv7em-none-eabihf" \
            "python3 -m venv $s/target/py-tools" "pip install -q maturin==1.16.0 pytest==9.2.0 mypy==2.4.1 numpy==2.4.6 pandas==3.1.1 mcap==1.6.0 mcap-ros2-support==0.6.0" \
            "pip download -q -d $s/target/py-tools/wheelhouse numpy==2.4.6 pandas==3.1.1 pyarrow==26.0.1 duckdb==2.0.1 wandb==0.31.0 tensorboard==2.21.0 mlflow-skinny==3.17.2"; do
  check "asked: $want" grep -qxF "$want" <<<"$(calls "$s")"
done
check "no cargo-fuzz without nightly, and said so" grep -q "skipping cargo-fuzz" "$s/log/stderr"
check "each install is announced" [ "$(grep -c '^\[setup\] \(adding\|installing\|downloading\)' "$s/log/stderr")" -eq 7 ]
check "nothing reported missing" bash -c "! grep -q 'NOT INSTALLED' '$s/log/stderr'"
: >"$s/log/calls"
status=0; run_setup "$s" || status=$?
check "a second run exits 0" [ "$status" -eq 0 ]
check "a second run installs nothing (calls: $(calls "$s" | grep -v ' list' | tr '\n' ';'))" \
  bash -c "! grep -v ' list' '$s/log/calls' | grep -q ."
check "a second run says everything is installed" grep -q "everything the tests use is installed" "$s/log/stderr"

echo "case 2: stubs that fail"
s="$work/fail"
make_sandbox "$s" fail
status=0; run_setup "$s" || status=$?
check "setup exits 0 (got $status)" [ "$status" -eq 0 ]
check "apt-get was asked for the same packages (asked: $(packages_asked "$s"))" [ "$(packages_asked "$s")" = "$expected" ]
for p in $expected; do
  check "names Debian package $p with the command" grep -q "Debian package $p\$" "$s/log/stderr"
done
check "says how to install by hand" grep -q "install by hand: apt-get install --no-install-recommends -t bookworm-backports qemu-system-arm" "$s/log/stderr"
check "says what skips" grep -q "the browser test of the HTML report skips" "$s/log/stderr"
check "names the rust targets" grep -q "rust target thumbv7em-none-eabihf" "$s/log/stderr"
check "names the Python tools" grep -q "Python tools (maturin==1.16.0" "$s/log/stderr"

echo "case 3: no package manager at all"
s="$work/none"
make_sandbox "$s" none
status=0; run_setup "$s" || status=$?
check "setup exits 0 (got $status)" [ "$status" -eq 0 ]
check "says apt-get is absent" grep -q "no apt-get on this machine" "$s/log/stderr"
check "names qemu-system-arm" grep -q "Debian package qemu-system-arm" "$s/log/stderr"
check "names python3" grep -q "python3 -- \|  python3$" "$s/log/stderr"

if [ "$fails" -gt 0 ]; then
  echo "setup-test: $fails check(s) FAILED for $setup" >&2
  exit 1
fi
echo "setup-test: all checks passed for $setup"
