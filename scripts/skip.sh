# Sourced by the test scripts: `loud_skip WHO WHAT` prints a banner on stderr, records the skip in
# $SDS_SKIP_LOG (test-all.sh lists every skip at its end, so a missing tool is never silent) and
# exits 0. WHAT says what was not tested and how to install what is missing.
loud_skip() {
  local who=$1; shift
  printf '\n[%s] ##################################################################\n' "$who" >&2
  printf '[%s] SKIPPED: %s\n' "$who" "$*" >&2
  printf '[%s] ##################################################################\n\n' "$who" >&2
  if [ -n "${SDS_SKIP_LOG:-}" ]; then printf '%s: %s\n' "$who" "$*" >>"$SDS_SKIP_LOG"; fi
  exit 0
}
# `need_tools WHO TOOL=PACKAGE...`: skips (loudly) unless every tool is on PATH.
need_tools() {
  local who=$1; shift
  local absent=() packages=() spec
  for spec in "$@"; do
    command -v "${spec%%=*}" >/dev/null 2>&1 || { absent+=("${spec%%=*}"); packages+=("${spec#*=}"); }
  done
  if [ ${#absent[@]} -gt 0 ]; then
    loud_skip "$who" "${absent[*]} not installed: not tested (bash scripts/setup.sh installs it; by hand: apt-get install $(printf '%s\n' "${packages[@]}" | sort -u | paste -sd' '))"
  fi
}
