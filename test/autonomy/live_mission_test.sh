#!/bin/sh
# The autonomy over LCM with the real processes (inside a private network namespace):
# tiller-sim + tiller-esc + tiller-mixer (seed 004 X drive) + tiller-path-follower +
# tiller-velocity-pid + tiller-station-keep, then tiller-mission with a short mission; the run
# is logged with lcm-logger and scored with tiller-score, which must say the path completed with
# no missed waypoint and a final error under 0.5 m. Args: SOURCE_DIR BUILD_DIR
set -u
src="$1"; bin="$2/bin"
work=$(mktemp -d)
pids=""
cleanup() { for p in $pids; do kill "$p" 2>/dev/null; done; wait 2>/dev/null; rm -rf "$work"; }
trap cleanup EXIT
start() { "$@" >"$work/$(basename "$1").out" 2>&1 & pids="$pids $!"; }
cd "$src"
v=seed004_usv_x
start lcm-logger --lcm-url="udpm://239.255.76.67:7667?ttl=0" -c "TILLER_.*" "$work/run.lcmlog"
start "$bin/tiller-sim" --config config/sim/sim.yaml --vehicle config/vehicles/$v.yaml
start "$bin/tiller-esc" --config config/esc/${v}_sim.yaml
start "$bin/tiller-mixer" --config config/mixer/$v.yaml
start "$bin/tiller-path-follower" --config config/guidance/default.yaml
start "$bin/tiller-velocity-pid" --config config/control/$v.yaml
start "$bin/tiller-station-keep" --config config/control/$v.yaml
sleep 1
start "$bin/tiller-mission" --mission test/autonomy/live_mission.yaml --path-id 1
sleep 12
for p in $pids; do kill "$p" 2>/dev/null; done
wait 2>/dev/null
pids=""
out=$("$bin/tiller-score" --log "$work/run.lcmlog" --mission test/autonomy/live_mission.yaml)
rc=$?
echo "$out"
[ $rc -eq 0 ] || { echo "FAIL: tiller-score exited $rc"; exit 1; }
echo "$out" | grep -q "missed 0" || { echo "FAIL: a waypoint was missed"; exit 1; }
t=$(echo "$out" | awk '/^time to complete/ {print $4}')
f=$(echo "$out" | awk '/^final position err/ {print $4}')
# The simulator's own odometry is the truth: no estimation line (it is for tiller-nav's).
echo "$out" | grep -E "^(estimation error|on the estimate)" && { echo "FAIL: the truth scored as an estimate"; exit 1; }
case "$t" in ''|*[!0-9.]*) echo "FAIL: the path did not complete ($t)"; exit 1 ;; esac
awk -v t="$t" 'BEGIN { exit !(t + 0 > 0) }' || { echo "FAIL: the path did not complete"; exit 1; }
awk -v f="$f" 'BEGIN { exit !(f < 0.5) }' || { echo "FAIL: final error $f m"; exit 1; }
echo "ok: completed in $t s, final error $f m"
