#!/bin/sh
# The main job's mission completes inside a private network namespace (tools/main-job runs its
# stack under tools/netns-run, as in CI): exit 0, every waypoint reached, a log and a PNG plot,
# tiller-failsafe's heartbeat OK and no failsafe event in the log,
# and its log replays through today's code with the launcher's manifest (PASS unchanged, FAIL
# with a changed gain). While it runs it prints the cockpit's URL, which serves the page.
# About 100 s of wall time (the default mission flies in real time). And it fails loudly (exit 1,
# with the reason) when a mission cannot complete in its time limit. Args: SOURCE_DIR BUILD_DIR
set -u
src="$1"; build="$2"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
# While the mission runs the main job prints the cockpit's URL (docs/operations.md, "The browser
# cockpit"), and the page answers through it. A free port of this side: another run's forward
# may hold 8088.
port=$(python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
TILLER_COCKPIT_PORT=$port TILLER_NO_SETUP=1 TILLER_BUILD_DIR="$build" TILLER_LOG_DIR="$tmp" "$src/tools/main-job" > "$tmp/out" 2>&1 &
job=$!
url=""; i=0
while [ -z "$url" ] && [ $i -lt 300 ] && kill -0 $job 2>/dev/null; do
  sleep 0.2; i=$((i + 1))
  url=$(sed -n 's/^tiller: cockpit: open \(http:[^ ]*\) while the mission runs$/\1/p' "$tmp/out")
done
case "$url" in
  "http://127.0.0.1:$port/#token="?*)
    python3 -c 'import sys, urllib.request; sys.stdout.write(urllib.request.urlopen(sys.argv[1].split("#")[0], timeout=10).read().decode())' "$url" |
      grep -q "<title>Tiller cockpit" || { echo "FAIL: the printed URL $url did not serve the cockpit's page"; fail=1; } ;;
  *) echo "FAIL: the main job printed no cockpit URL on port $port (got '$url')"; fail=1 ;;
esac
wait $job; rc=$?
out=$(cat "$tmp/out")
echo "$out" | grep -v '^logger' | tail -40
[ $rc -eq 0 ] || { echo "FAIL: main job exited $rc"; fail=1; }
echo "$out" | grep -q "mission complete in" || { echo "FAIL: no 'mission complete'"; fail=1; }
echo "$out" | grep -Eq "waypoints +5 \(reached in order 5, missed 0\)" || { echo "FAIL: not every waypoint reached"; fail=1; }
log=$(echo "$out" | sed -n 's/^tiller: log  //p')
png=$(echo "$out" | sed -n 's/^tiller: plot //p')
[ -s "$log" ] || { echo "FAIL: no log at '$log'"; fail=1; }
[ -s "$png" ] && head -c 4 "$png" | grep -q PNG || { echo "FAIL: no PNG at '$png'"; fail=1; }
# tiller-failsafe runs in the main job on the simulated sensors (issue 14 item 6) and a healthy run
# trips nothing: its heartbeat is in the log and ends OK ("no failsafe event"), and every
# TILLER_VEHICLE_STATUS has no latched event and no action.
hb=$("$build/bin/tiller-log" csv "$log" TILLER_HEARTBEAT_FAILSAFE --fields state,status 2>&1 | tail -1)
echo "failsafe heartbeat (last): $hb"
echo "$hb" | grep -Eq '^[0-9.]+,0,no failsafe event$' || { echo "FAIL: the failsafe's last heartbeat is not OK 'no failsafe event': $hb"; fail=1; }
vs=$("$build/bin/tiller-log" csv "$log" TILLER_VEHICLE_STATUS --fields latched,action 2>&1 |
  awk -F, 'NR > 1 { n++; if ($2 != 0 || $3 != 0) bad++ } END { print n + 0, bad + 0 }')
echo "vehicle status: $vs (messages, with an event or an action)"
set -- $vs
[ "${1:-0}" -gt 100 ] && [ "${2:-1}" -eq 0 ] || { echo "FAIL: TILLER_VEHICLE_STATUS: $vs (expected > 100 messages, 0 with an event)"; fail=1; }
# The newcomer's replay (docs/operations.md): tiller-replay LOG, from another directory, with the manifest
# tiller-launch wrote next to the log. Nothing changed: PASS (exit 0), every replayable process
# replayed as a live log. A changed gain (the path follower's max_speed 1.5 -> 1.6 m/s): FAIL
# (exit 1) naming the channel and the first difference.
manifest="${log%.lcmlog}.replay.yaml"
[ -s "$manifest" ] || { echo "FAIL: no replay manifest $manifest"; fail=1; }
rout=$(cd /tmp && "$build/bin/tiller-replay" "$log" 2>&1); rrc=$?
echo "$rout" | grep -E "^[a-z]|summary|DIFFERENT|first difference"
if [ $rrc -ne 0 ]; then
  # A live log is UDP multicast as lcm-logger heard it: on a loaded machine it can lose or stamp
  # late a one-shot message the processes got (the mission's START at ~0.6 s, in the start-up
  # rush), and the replayed mixer then never leaves WAIT_NEUTRAL (seen in CI: every thruster
  # command differs from ~1 s on). A second main job tells that from a determinism bug, which
  # fails both times. The first run's differences are printed above either way.
  echo "NOTE: the first main-job log did not replay (exit $rrc); flying the main job again"
  mkdir -p "$tmp/again"
  TILLER_NO_SETUP=1 TILLER_BUILD_DIR="$build" TILLER_LOG_DIR="$tmp/again" "$src/tools/main-job" > "$tmp/again.out" 2>&1
  log2=$(sed -n 's/^tiller: log  //p' "$tmp/again.out")
  rout2=$(cd /tmp && "$build/bin/tiller-replay" "$log2" 2>&1); rrc=$?
  echo "$rout2" | grep -E "^tiller-replay|summary.*FAIL|first difference" | head -20
  if [ $rrc -eq 0 ]; then
    echo "NOTE: the second main-job log replays: PASS (the first log lost a message)"
    rout=$rout2  # the checks below read the passing replay
  fi
fi
[ $rrc -eq 0 ] || { echo "FAIL: replaying the unchanged main-job log gave exit $rrc, expected 0 (PASS), twice"; fail=1; }
for p in esc mixer path-follower velocity-pid station-keep sim; do
  echo "$rout" | grep -q "^$p (config /" || { echo "FAIL: $p was not replayed"; fail=1; }
done
# The verdict line counts only what it checked: on a live log the integrating processes (sim,
# velocity-pid, station-keep) are informational, and the line says so.
vline=$(echo "$rout" | grep "^tiller-replay: ")
echo "$vline" | grep -Eq "^tiller-replay: PASS \(3 processes checked: [a-z, -]+; 3 informational: [a-z, -]+; live log" ||
  { echo "FAIL: the verdict line does not say 3 processes checked, 3 informational: $vline"; fail=1; }
for p in esc mixer path-follower; do
  echo "$vline" | sed 's/;.*informational.*//' | grep -Eq "[:,] $p(,|$)" || { echo "FAIL: $p is not among the checked processes: $vline"; fail=1; }
done
for p in sim velocity-pid station-keep; do
  echo "$vline" | sed 's/.*informational: //; s/;.*//' | grep -Eq "(^|, )$p(,|$)" || { echo "FAIL: $p is not among the informational processes: $vline"; fail=1; }
done
sed -e 's/^  max_speed: 1.5 /  max_speed: 1.6 /' -e "s|vehicle_file: config/|vehicle_file: $src/config/|" "$src/config/guidance/otter.yaml" > "$tmp/guidance_changed.yaml"
cmp -s "$src/config/guidance/otter.yaml" "$tmp/guidance_changed.yaml" && { echo "FAIL: could not change max_speed (config changed?)"; fail=1; }
rout=$(cd /tmp && "$build/bin/tiller-replay" "$log" --process path-follower --config "$tmp/guidance_changed.yaml" 2>&1); rrc=$?
echo "$rout" | grep -E "DIFFERENT|first difference|^tiller-replay"
[ $rrc -eq 1 ] || { echo "FAIL: a changed gain gave exit $rrc, expected 1 (FAIL)"; fail=1; }
echo "$rout" | grep -q "TILLER_VELOCITY_SETPOINT *DIFFERENT" || { echo "FAIL: the setpoint difference is not reported"; fail=1; }
# The new value is the changed gain; the old one is usually 1.5, but on a loaded machine the
# first differing message can be one the live run published before its first odometry (0).
echo "$rout" | grep -Eq "first difference: message [0-9]+ at t=[0-9.]+ s, velocity\[0\]: old [-0-9.e]+, new 1.6" ||
  { echo "FAIL: the first difference (time, field, old, new 1.6) is not reported"; fail=1; }

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
