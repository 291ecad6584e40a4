#!/bin/sh
# Every tiller-<name> program takes --help (exit 0; its shape is help_test.sh's). The processes
# of the stack refuse a missing config file with exit status 2 and a message that names the
# file, and never crash; so do a missing, malformed or group/world-readable signing key file
# (--key-file), and --require-signed without a key. Args: BUILD_DIR
set -u
bin="$1/bin"
fail=0
n=0
keys=$(mktemp -d)
trap 'rm -rf "$keys"' EXIT
"$bin/tiller-key" new "$keys/ok.key" > /dev/null || { echo "FAIL: tiller-key new failed"; fail=1; }
[ "$(stat -c %a "$keys/ok.key")" = 600 ] || { echo "FAIL: tiller-key new did not make a 0600 file"; fail=1; }
"$bin/tiller-key" check "$keys/ok.key" | grep -Eq "valid key file, key id [0-9a-f]{8}$" ||
  { echo "FAIL: tiller-key check did not accept its own key"; fail=1; }
"$bin/tiller-key" new "$keys/ok.key" > /dev/null 2>&1 && { echo "FAIL: tiller-key new overwrote a key without --force"; fail=1; }
cp "$keys/ok.key" "$keys/open.key"; chmod 644 "$keys/open.key"
echo "not a key" > "$keys/bad.key"; chmod 600 "$keys/bad.key"
for p in "$bin"/tiller-*; do
  [ -x "$p" ] || continue
  n=$((n + 1))
  name=$(basename "$p")
  out=$(timeout 10 "$p" --help 2>&1); rc=$?
  if [ $rc -ne 0 ]; then echo "FAIL: $name --help exited $rc"; fail=1; continue; fi
  case "$name" in
    tiller-teleop|tiller-path-follower|tiller-velocity-pid|tiller-station-keep|tiller-mixer|tiller-esc|tiller-sim|tiller-launch)
      out=$(timeout 10 "$p" --config /nonexistent/tiller-cli-test.yaml 2>&1 </dev/null); rc=$?
      if [ $rc -ne 2 ]; then echo "FAIL: $name with a missing config exited $rc (expected 2): $out"; fail=1; fi
      echo "$out" | grep -q "/nonexistent/tiller-cli-test.yaml" || { echo "FAIL: $name does not name the missing file: $out"; fail=1; }
      for k in missing.key open.key bad.key; do
        out=$(timeout 10 "$p" --key-file "$keys/$k" 2>&1 </dev/null); rc=$?
        if [ $rc -ne 2 ]; then echo "FAIL: $name with key file $k exited $rc (expected 2): $out"; fail=1; fi
        echo "$out" | grep -q "key file '$keys/$k'" || { echo "FAIL: $name does not name the key file $k: $out"; fail=1; }
      done
      out=$(timeout 10 "$p" --require-signed 2>&1 </dev/null); rc=$?
      [ $rc -eq 2 ] && echo "$out" | grep -q "require_signed is on but no key file" ||
        { echo "FAIL: $name --require-signed without a key: exit $rc: $out"; fail=1; }
      ;;
  esac
  echo "ok: $name"
done
[ $n -gt 0 ] || { echo "FAIL: no tiller-* programs in $bin"; exit 1; }
# tiller-nav's datum options: a bad --datum names the flag and the form; a mission without a
# home is refused by --datum-mission, naming the file (both before any LCM is opened).
src=$(cd "$(dirname "$0")/../.." && pwd)
for d in "59.4" "95,10" "59.4,x" "59.4,10.6,1,2"; do
  out=$(cd "$src" && timeout 10 "$bin/tiller-nav" --datum "$d" 2>&1 </dev/null); rc=$?
  [ $rc -eq 2 ] && echo "$out" | grep -q -- "--datum: expected LAT,LON\[,ALT\]" ||
    { echo "FAIL: tiller-nav --datum '$d': exit $rc: $out"; fail=1; }
done
out=$(cd "$src" && timeout 10 "$bin/tiller-nav" --datum-mission config/missions/default.yaml 2>&1 </dev/null); rc=$?
[ $rc -eq 2 ] && echo "$out" | grep -q "default.yaml: the mission has no home position" ||
  { echo "FAIL: tiller-nav --datum-mission without a home: exit $rc: $out"; fail=1; }
exit $fail
