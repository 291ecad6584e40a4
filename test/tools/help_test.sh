#!/bin/sh
# The shape of every tiller-* program's --help (each program in BUILD_DIR/bin, so a new one is
# covered at once): exit 0; exactly one "Usage: tiller-NAME ..." line; no option listed twice; no
# line with two "(default"; no option listed that the program then refuses ("not taken",
# "unknown option" when it is given, with a bad value); and a positional argument the program
# does not take is refused with exit 2 and a message naming it. Every check ends in the option
# parser (extra positional arguments are always given), so nothing opens a device or LCM; the
# test still runs under tools/netns-run. Args: BUILD_DIR
set -u
bin="$1/bin"
fail=0
n=0
extra="tiller-unexpected-1 tiller-unexpected-2 tiller-unexpected-3 tiller-unexpected-4 tiller-unexpected-5 tiller-unexpected-6"
for p in "$bin"/tiller-*; do
  [ -x "$p" ] || continue
  n=$((n + 1))
  name=$(basename "$p")
  ok=1
  bad() { echo "FAIL: $name: $*"; fail=1; ok=0; }
  help=$(timeout 10 "$p" --help 2>&1); rc=$?
  [ $rc -eq 0 ] || bad "--help exited $rc"
  usages=$(printf '%s\n' "$help" | grep -c 'Usage:')
  [ "$usages" -eq 1 ] || bad "--help has $usages 'Usage:' lines (expected 1)"
  printf '%s\n' "$help" | grep -q "^Usage: $name" || bad "--help does not start with 'Usage: $name'"
  opts=$(printf '%s\n' "$help" | sed -n 's/^  \(--[a-z0-9-]*\).*/\1/p')
  printf '%s\n' "$opts" | grep -qx -- --help || bad "--help does not list --help"
  dups=$(printf '%s\n' "$opts" | sort | uniq -d)
  [ -z "$dups" ] || bad "options listed twice: $dups"
  twice=$(printf '%s\n' "$help" | grep '(default.*(default')
  [ -z "$twice" ] || bad "a default shown twice: $twice"
  printf '%s\n' "$help" | grep -qiE 'not taken|unknown option' && bad "--help lists an option it refuses"
  for o in $opts; do
    [ "$o" = --help ] && continue
    # shellcheck disable=SC2086
    out=$(timeout 10 "$p" "$o" tiller-bad-value $extra </dev/null 2>&1); rc=$?
    if printf '%s\n' "$out" | grep -qiE 'not taken|unknown option'; then
      bad "$o is listed but refused: $out"
    fi
    [ $rc -eq 2 ] || bad "$o with extra arguments exited $rc (expected 2): $out"
  done
  # shellcheck disable=SC2086
  out=$(timeout 10 "$p" $extra </dev/null 2>&1); rc=$?
  [ $rc -eq 2 ] || bad "unexpected positional arguments exited $rc (expected 2): $out"
  printf '%s\n' "$out" | grep -q "unexpected argument 'tiller-unexpected-[0-9]'" ||
    bad "unexpected positional arguments are not named: $out"
  [ $ok -eq 1 ] && echo "ok: $name ($(printf '%s\n' "$opts" | wc -l) options)"
done
[ $n -gt 0 ] || { echo "FAIL: no tiller-* programs in $bin"; exit 1; }
exit $fail
