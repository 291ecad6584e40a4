#!/bin/sh
# Issue 13, finding 5: a live simulated run starts where the mission file's start: says. The main
# job's launch file (config/launch/sim_usv_mission.yaml) with MISSION naming a mission that starts
# at north 6, east -3, heading 90 deg: the simulator's first odometry is there. (Before: the
# launch file started tiller-sim at the simulator config's pose, 0 0 0, whatever the mission.)
# Runs inside tools/netns-run (LCM stays in a private namespace). Args: SOURCE_DIR BUILD_DIR
set -u
src="$1"
bin="$2/bin"
tmp=$(mktemp -d)
launcher=""
trap '[ -n "$launcher" ] && kill -KILL "$launcher" 2>/dev/null; rm -rf "$tmp"' EXIT
cat > "$tmp/start.yaml" <<'M'
name: start-test
start: {north: 6, east: -3, heading_deg: 90}
time_limit_s: 60
waypoints:
  - [6, -3]
  - [6, 10]
M
"$bin/tiller-key" new "$tmp/sim.key" > /dev/null || { echo "FAIL: tiller-key new"; exit 1; }
export MISSION="$tmp/start.yaml" TILLER_KEY_FILE="$tmp/sim.key"
"$bin/tiller-launch" "$src/config/launch/sim_usv_mission.yaml" --only sim \
  --log-file "$tmp/run.lcmlog" > "$tmp/out" 2>&1 &
launcher=$!
sleep 3
kill -TERM $launcher; wait $launcher; rc=$?; launcher=""
fail=0
[ $rc -eq 0 ] || { echo "FAIL: tiller-launch exited $rc"; tail -20 "$tmp/out"; fail=1; }
grep -q "starts at north 6.00 m, east -3.00 m, heading 90.0 deg (from $tmp/start.yaml)" "$tmp/out" ||
  { echo "FAIL: tiller-sim did not say it starts at the mission's start:"; grep sim "$tmp/out" | head -5; fail=1; }
first=$("$bin/tiller-log" csv "$tmp/run.lcmlog" TILLER_ODOMETRY --fields position,orientation | sed -n 2p)
echo "first odometry: $first"
echo "$first" | awk -F, '{ d = ($2-6)^2 + ($3+3)^2; h = $7 - 1.5707963; exit !(d < 1e-6 && h < 1e-6 && h > -1e-6) }' ||
  { echo "FAIL: the first odometry is not at north 6, east -3, heading pi/2: $first"; fail=1; }
[ $fail -eq 0 ] && echo "sim_start_launch_test: OK"
exit $fail
