#!/bin/sh
# An ROV's mission through the real processes (issue 34): tiller-launch runs
# config/launch/sim_bluerov2_mission.yaml (tiller-sim with the DVL, tiller-nav on it, tiller-mission,
# tiller-path-follower, tiller-rov-control's waypointing, the mixer, the ESC, the failsafe) in this
# private network namespace (the test runs under tools/netns-run) with test/ops/rov_mission_live.yaml:
# the run ends by `done` (exit 0); from the log: rov-control in waypointing, the path complete, the
# vehicle within 0.2 m of the goal at the end (the DVL's dead reckoning drifts) and at the path's
# 1 m depth within 5 cm over the last 2 s, every thruster command neutral before the mission's START, and
# the log replays through tiller-replay without a config or usage error (exit <= 1, as in
# launch_replay_test: a live log's timing under load can differ from the lockstep replay by a
# message; the bit-for-bit replay of an ROV run is asserted in lockstep by runtool_test). Args:
# SOURCE_DIR BUILD_DIR
set -u
src="$1"; build="$2"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
"$build/bin/tiller-key" new "$tmp/key" > /dev/null || exit 1
cd "$src" || exit 1
PATH="$build/bin:$PATH" MISSION=test/ops/rov_mission_live.yaml TILLER_KEY_FILE="$tmp/key" \
  timeout 120 "$build/bin/tiller-launch" config/launch/sim_bluerov2_mission.yaml \
  --log-file "$tmp/run.lcmlog" > "$tmp/out" 2>&1
rc=$?
grep -v '^logger' "$tmp/out" | tail -15
[ $rc -eq 0 ] || { echo "FAIL: tiller-launch exited $rc (expected 0: done saw the path complete)"; fail=1; }
log="$tmp/run.lcmlog"
[ -s "$log" ] || { echo "FAIL: no log"; exit 1; }
L="$build/bin/tiller-log"
arb=$("$L" csv "$log" TILLER_ARBITRATION --fields mode,active_source | tail -1)
echo "last arbitration (mode, source): $arb"
echo "$arb" | grep -Eq '^[0-9.]+,2,4$' || { echo "FAIL: not waypointing (2) on tiller-rov-control's wrench (4): $arb"; fail=1; }
prog=$("$L" csv "$log" TILLER_PATH_PROGRESS --fields complete | tail -1)
echo "$prog" | grep -Eq ',1$' || { echo "FAIL: the path is not complete: $prog"; fail=1; }
# The truth: distance to the goal (4, 0) at the end, the depth error to 1 m over the last 2 s.
res=$("$L" csv "$log" TILLER_GROUND_TRUTH --fields position | awk -F, '
  NR > 1 { t[NR] = $1; n[NR] = $2; e[NR] = $3; d[NR] = $4; last = NR }
  END { worst_d = 0
        for (i = 2; i <= last; i++) if (t[i] >= t[last] - 2) {
          x = d[i] - 1; if (x < 0) x = -x; if (x > worst_d) worst_d = x }
        printf "%.3f %.3f\n", sqrt((n[last] - 4) ^ 2 + e[last] ^ 2), worst_d }')
echo "distance to the goal at the end, largest depth error over the last 2 s (m): $res"
set -- $res
awk -v p="$1" -v d="$2" 'BEGIN { exit !(p <= 0.2 && d <= 0.05) }' ||
  { echo "FAIL: expected within 0.2 m of the goal and 0.05 m of 1 m depth"; fail=1; }
# Before the mission's START (TILLER_MISSION_COMMAND) every thruster command is neutral.
start=$("$L" csv "$log" TILLER_MISSION_COMMAND --fields command | awk -F, 'NR == 2 { print $1 }')
[ -n "$start" ] || { echo "FAIL: no START in the log"; fail=1; start=0; }
early=$("$L" csv "$log" TILLER_THRUSTER_COMMAND --fields command | awk -F, -v s="$start" '
  NR > 1 && $1 < s { for (i = 2; i <= NF; i++) if ($i != 0) bad++ } END { print bad + 0 }')
echo "START at $start s; thruster commands off neutral before it: $early"
[ "$early" -eq 0 ] || { echo "FAIL: thrust before the mission's START"; fail=1; }
rout=$("$build/bin/tiller-replay" "$log" 2>&1); rrc=$?
echo "$rout" | tail -1
[ $rrc -eq 0 ] || echo "replay differs (live timing): $(echo "$rout" | grep -E 'DIFFERENT|first difference' | head -3)"
[ $rrc -le 1 ] || { echo "FAIL: tiller-replay exited $rrc (a config or usage error)"; fail=1; }
echo "$rout" | grep -Eqi "config error|cannot open" && { echo "FAIL: a config error"; fail=1; }
echo "$rout" | grep -q "processes checked: esc, mixer, path-follower" || { echo "FAIL: esc, mixer and path-follower not all replayed"; fail=1; }
[ $fail -eq 0 ] && echo "rov_mission_live_test: PASS"
exit $fail
