#!/bin/sh
# Every program of the stack starts with its default config from a directory outside the
# repository (the configs are found in the source tree: runtime/app.cpp resolve_path) and ends
# cleanly on SIGTERM (status 0); none says "cannot open config file". Runs inside the private
# network namespace of tools/netns-run (the programs open udpm://). Args: BUILD_DIR
set -u
bin="$(cd "$1" && pwd)/bin"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work" || exit 1
fail=0
# tiller-mixer --describe exits at once: the default config and its vehicle file were found.
out=$("$bin/tiller-mixer" --describe 2>&1); rc=$?
if [ $rc -ne 0 ]; then echo "FAIL: tiller-mixer --describe from $work exited $rc: $out"; fail=1; fi
names="velocity-pid station-keep rov-control path-follower mixer teleop esc sim"
for name in $names; do
  "$bin/tiller-$name" >"$work/$name.log" 2>&1 </dev/null &
  echo $! >"$work/$name.pid"
done
# 3 s for a config error to show (a bad config exits with 2 within milliseconds of starting).
sleep 3
for name in $names; do
  pid=$(cat "$work/$name.pid")
  kill -TERM "$pid" 2>/dev/null
  wait "$pid"; rc=$?
  if grep -q "cannot open" "$work/$name.log" || [ $rc -ne 0 ]; then
    echo "FAIL: tiller-$name from $work: exit $rc: $(cat "$work/$name.log")"
    fail=1
  else
    echo "ok: tiller-$name"
  fi
done
exit $fail
