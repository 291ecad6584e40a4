#!/bin/sh
# The main job's mission completes inside a private network namespace (tools/main-job runs its
# stack under tools/netns-run, as in CI): exit 0, every waypoint reached, a log and a PNG plot.
# About 100 s of wall time (the default mission flies in real time). And it fails loudly (exit 1,
# with the reason) when a mission cannot complete in its time limit. Args: SOURCE_DIR BUILD_DIR
set -u
src="$1"; build="$2"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
out=$(TILLER_NO_SETUP=1 TILLER_BUILD_DIR="$build" TILLER_LOG_DIR="$tmp" "$src/tools/main-job" 2>&1); rc=$?
echo "$out" | grep -v '^logger' | tail -40
fail=0
[ $rc -eq 0 ] || { echo "FAIL: main job exited $rc"; fail=1; }
echo "$out" | grep -q "mission complete in" || { echo "FAIL: no 'mission complete'"; fail=1; }
echo "$out" | grep -Eq "waypoints +5 \(reached in order 5, missed 0\)" || { echo "FAIL: not every waypoint reached"; fail=1; }
log=$(echo "$out" | sed -n 's/^tiller: log  //p')
png=$(echo "$out" | sed -n 's/^tiller: plot //p')
[ -s "$log" ] || { echo "FAIL: no log at '$log'"; fail=1; }
[ -s "$png" ] && head -c 4 "$png" | grep -q PNG || { echo "FAIL: no PNG at '$png'"; fail=1; }
# Clean stop: no process needed SIGKILL or crashed while stopping.
echo "$out" | grep -E "needed SIGKILL|killed by SIG(SEGV|ABRT)" && { echo "FAIL: unclean stop"; fail=1; }

# A mission that cannot complete within its time limit (3 s) fails loudly.
sed 's/^time_limit_s: .*/time_limit_s: 3/' "$src/test/data/golden/mission_short.yaml" > "$tmp/too_short.yaml"
out=$(MISSION="$tmp/too_short.yaml" TILLER_NO_SETUP=1 TILLER_BUILD_DIR="$build" TILLER_LOG_DIR="$tmp" "$src/tools/main-job" 2>&1); rc=$?
echo "$out" | tail -4
[ $rc -eq 1 ] || { echo "FAIL: an incomplete mission gave exit $rc, expected 1"; fail=1; }
echo "$out" | grep -q "tiller: FAILED after .*the mission did not complete" || { echo "FAIL: no loud reason"; fail=1; }
echo "$out" | grep -q "FAILED: TILLER_PATH_PROGRESS.complete never == 1" || { echo "FAIL: the done process did not say why"; fail=1; }
[ $fail -eq 0 ] && echo "main_job_test: ok"
exit $fail
