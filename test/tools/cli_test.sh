#!/bin/sh
# Every tiller-<name> program takes --help (exit 0; its shape is help_test.sh's). The processes
# of the stack refuse a missing config file with exit status 2 and a message that names the
# file, and never crash. Args: BUILD_DIR
set -u
bin="$1/bin"
fail=0
n=0
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
      ;;
  esac
  echo "ok: $name"
done
[ $n -gt 0 ] || { echo "FAIL: no tiller-* programs in $bin"; exit 1; }
exit $fail
