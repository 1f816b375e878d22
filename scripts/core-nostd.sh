#!/usr/bin/env bash
# monitor-core on bare Cortex-M, with proof:
#  1. the library builds for thumbv7em-none-eabihf and thumbv7m-none-eabi, with and without defmt;
#  2. a #![no_std] #![no_main] binary that uses Monitor::push/finish and json::encode
#     (monitor-core/examples/nostd_link.rs) links for thumbv7em-none-eabihf, and `nm` finds no
#     symbol of std or alloc in it (__rust_alloc, __rust_dealloc, alloc::, std::);
#  3. no function of monitor_core in that image branches to a panic (bounds checks, unwrap,
#     overflow): the per-frame code has no panic path.
# Needs the thumb targets and binutils-arm-none-eabi (or llvm-nm/llvm-objdump): scripts/setup.sh.
set -euo pipefail
cd "$(dirname "$0")/.."

fail() { printf 'core-nostd: FAIL: %s\n' "$*" >&2; exit 1; }
# shellcheck source=skip.sh
source scripts/skip.sh

installed=$(rustup target list --installed 2>/dev/null || true)
for t in thumbv7em-none-eabihf thumbv7m-none-eabi; do
  grep -qx "$t" <<<"$installed" || loud_skip core-nostd "target $t is not installed: the no_std build was not tested (bash scripts/setup.sh adds it; by hand: rustup target add $t)"
  cargo build -q -p monitor-core --release --target "$t"
  cargo build -q -p monitor-core --release --target "$t" --features defmt
  echo "monitor-core builds for $t (with and without defmt)"
done

# 2. Link proof.
target=thumbv7em-none-eabihf
cargo build -q -p monitor-core --release --target "$target" --example nostd_link
dir=${CARGO_TARGET_DIR:-target}
elf="$dir/$target/release/examples/nostd_link"
[ -f "$elf" ] || fail "no image at $elf"

if command -v arm-none-eabi-nm >/dev/null 2>&1; then NM=arm-none-eabi-nm
elif command -v llvm-nm >/dev/null 2>&1; then NM=llvm-nm
else loud_skip core-nostd "neither arm-none-eabi-nm nor llvm-nm: the image's symbols were not checked (bash scripts/setup.sh; by hand: apt-get install binutils-arm-none-eabi)"; fi
if command -v arm-none-eabi-objdump >/dev/null 2>&1; then OBJDUMP=arm-none-eabi-objdump
elif command -v llvm-objdump >/dev/null 2>&1; then OBJDUMP=llvm-objdump
else loud_skip core-nostd "neither arm-none-eabi-objdump nor llvm-objdump: the panic-branch check was not run (bash scripts/setup.sh; by hand: apt-get install binutils-arm-none-eabi)"; fi

# Symbols of std or alloc: the allocator shims, or a path starting at std:: / alloc:: (not
# core::alloc::, which is part of core). Raw legacy-mangled names are checked too.
forbidden='__rust_alloc|__rust_dealloc|__rust_realloc|__rust_alloc_zeroed|__rg_alloc|(^|[^:A-Za-z0-9_])(std|alloc)::|_ZN3std|_ZN5alloc'
# The check must be able to fail: try it on names that must match, and on one that must not.
for probe in "00000000 T __rust_alloc" "00000000 T alloc::raw_vec::finish_grow" \
             "00000000 T <std::io::Write>::write" "00000000 T _ZN5alloc7raw_vec11finish_grow"; do
  grep -Eq "$forbidden" <<<"$probe" || fail "the symbol filter misses '$probe'"
done
! grep -Eq "$forbidden" <<<"00000000 T core::alloc::layout::Layout" || fail "filter too broad"

syms=$({ "$NM" -C "$elf"; "$NM" "$elf"; } 2>/dev/null)
grep -q 'monitor_core::' <<<"$syms" || fail "no monitor_core symbol in $elf: nothing was checked"
grep -Eq ' _start$' <<<"$syms" || fail "no _start in $elf"
if bad=$(grep -E "$forbidden" <<<"$syms"); then
  printf '%s\n' "$bad" | head -20 >&2
  fail "std/alloc symbols linked into $elf"
fi
hex=$("$NM" -S "$elf" | awk '$4 == "NOSTD_MONITOR" { print $2 }')
size=$([ -n "$hex" ] && printf '%d' "0x$hex" || true)
echo "no_std link proof: $elf links for $target with no std/alloc symbol ($(wc -l <<<"$syms") symbols checked)"
echo "  size_of::<Monitor>() on $target: ${size:-?} bytes (NOSTD_MONITOR)"

# 3. No panic path in monitor_core's own functions (inlined heapless code included).
panics=$("$NM" -C "$elf" | awk '$3 ~ /^core::panicking::|^core::slice::index::slice_.*fail|^core::option::unwrap_failed|^core::result::unwrap_failed|^core::option::expect_failed/ { sub(/^0+/, "", $1); print $1 }' | paste -sd'|' -)
if [ -n "$panics" ]; then
  callers=$("$OBJDUMP" -d -C "$elf" | awk -v p="$panics" '
    /^[0-9a-f]+ <.*>:$/ { fn = $0; next }
    $0 ~ ("[ \t](bl|b|b\\.w|blx)[ \t]+(0x)?0*(" p ")([ \t]|$)") { print fn }' | sort -u)
  # _start and nostd_link:: hold whatever was inlined into the example's own code.
  if core_callers=$(grep -E 'monitor_core::|<_start>|nostd_link::' <<<"$callers"); then
    printf '%s\n' "$core_callers" >&2
    fail "monitor_core functions with a panic path"
  fi
  others=$(grep -c . <<<"$callers" || true)
  echo "no panic path in monitor_core functions ($others functions of other crates keep one:" \
       "$(sed -E 's/^[0-9a-f]+ <(.*)>:$/\1/; s/^[<&]+(mut )?//' <<<"$callers" | awk -F'::' '{print $1}' | sort -u | paste -sd, -))"
else
  echo "no panic path at all in $elf"
fi
