#!/bin/sh
# tiller-run end to end (no LCM: it runs in lockstep in one process): the default mission with a
# log prints tiller-score's numbers, and tiller-score on the log prints the same lines; the log
# reads back in tiller-log summary and replays through tiller-replay bit for bit; two runs write
# identical log bytes; a 2x2 sweep prints 4 rows and writes a PNG; a smoke subset of the missions
# benchmark matrix (tools/missions-matrix) prints its row; bad flags exit 2 naming them.
# Args: SOURCE_DIR BUILD_DIR
set -u
src="$1"
bin="$2/bin"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
bad() { echo "FAIL: $*"; fail=1; }
cd "$tmp" || exit 1   # from another directory: configs are found in the source tree

# 1. One run, logged; its scores are tiller-score's on the log.
"$bin/tiller-run" config/missions/default.yaml --log run.lcmlog > run.out 2>&1; rc=$?
cat run.out
[ $rc -eq 0 ] || bad "tiller-run exited $rc"
grep -q "mission complete" run.out || bad "no 'mission complete'"
grep -q "waypoints           5 (reached in order 5, missed 0)" run.out || bad "not 5 of 5 waypoints"
[ -s run.replay.yaml ] || bad "no replay manifest"
"$bin/tiller-score" --log run.lcmlog --mission "$src/config/missions/default.yaml" > score.out 2>&1 ||
  bad "tiller-score failed: $(cat score.out)"
sed -n '/^pose from/,/^VRX station/p' run.out > run.scores
cmp -s run.scores score.out || { bad "tiller-run's scores differ from tiller-score's on its log"; diff run.scores score.out; }

# 2. The log: tiller-log summary reads it and names the live run's channels; tiller-replay
#    replays every process bit for bit (the manifest names the configs).
"$bin/tiller-log" summary run.lcmlog > summary.out 2>&1 || bad "tiller-log summary failed: $(tail -3 summary.out)"
for ch in TILLER_ODOMETRY TILLER_GROUND_TRUTH TILLER_ESC_OUTPUT TILLER_THRUSTER_COMMAND \
          TILLER_WRENCH_VELOCITY TILLER_WRENCH_STATION TILLER_PATH TILLER_PATH_PROGRESS \
          TILLER_VELOCITY_SETPOINT TILLER_ARM_STATE TILLER_MISSION_COMMAND TILLER_HEARTBEAT_SIM \
          TILLER_HEARTBEAT_MIXER TILLER_HEARTBEAT_MISSION; do
  grep -q "$ch" summary.out || bad "summary lacks $ch"
done
"$bin/tiller-replay" run.lcmlog > replay.out 2>&1 || { bad "tiller-replay of the log failed"; tail -15 replay.out; }
grep -q "tiller-replay: PASS" replay.out || bad "no PASS from tiller-replay: $(tail -3 replay.out)"

# 2b. On estimated state the estimator replays too: tiller-nav's odometry bit for bit (a Kalman
#     filter integrates every input: one changed input or setting changes every later output);
#     a changed setting (the fix's latency 0.1 -> 0.2 s) is a FAIL naming TILLER_ODOMETRY.
"$bin/tiller-run" config/missions/default.yaml --odometry estimated --log est.lcmlog > est.out 2>&1 ||
  bad "tiller-run --odometry estimated failed: $(tail -3 est.out)"
grep -q "^  nav: .*config/nav/usv_sim.yaml" est.replay.yaml || bad "the estimated run's manifest names no nav: $(cat est.replay.yaml)"
"$bin/tiller-replay" est.lcmlog > est_replay.out 2>&1 || { bad "tiller-replay of the estimated log failed"; tail -15 est_replay.out; }
grep -Eq "^tiller-replay: PASS \(7 processes checked: .*nav" est_replay.out || bad "nav not checked: $(tail -3 est_replay.out)"
grep -Eq "^  TILLER_ODOMETRY +matching \([0-9]{4,} messages\)" est_replay.out || bad "nav's odometry not matched bit for bit"
sed 's/^  latency_s: 0.1 /  latency_s: 0.2 /' "$src/config/nav/usv_sim.yaml" > nav_changed.yaml
cmp -s "$src/config/nav/usv_sim.yaml" nav_changed.yaml && bad "could not change gnss.latency_s"
"$bin/tiller-replay" est.lcmlog --process nav --config nav_changed.yaml > est_changed.out 2>&1; rc=$?
[ $rc -eq 1 ] || bad "a changed nav setting gave exit $rc, expected 1 (FAIL)"
grep -q "TILLER_ODOMETRY *DIFFERENT" est_changed.out || bad "the odometry difference is not reported: $(tail -5 est_changed.out)"

# 3. Determinism: the same run again writes the same bytes.
"$bin/tiller-run" config/missions/default.yaml --log again.lcmlog > /dev/null 2>&1
cmp -s run.lcmlog again.lcmlog || bad "two runs wrote different logs"

# 4. A 2x2 sweep: 4 rows, a CSV and a PNG.
"$bin/tiller-run" config/missions/default.yaml --jobs 2 --plot grid.png \
  --sweep guidance.follower.max_speed=1.2:1.5:2 --sweep2 current-speed=0,0.3 > sweep.out 2>&1; rc=$?
cat sweep.out
[ $rc -eq 0 ] || bad "the sweep exited $rc"
rows=$(grep -cE '^1\.(2|5) +(0|0\.3) +[0-9]' sweep.out)
[ "$rows" -eq 4 ] || bad "the sweep printed $rows rows (expected 4)"
[ "$(head -c 4 grid.png | od -An -c | tr -d ' ')" = "211PNG" ] || bad "grid.png is not a PNG"
[ "$(wc -l < grid.csv)" -eq 5 ] || bad "grid.csv has $(wc -l < grid.csv) lines (expected 5)"

# 5. The missions benchmark matrix (tools/missions-matrix), a smoke subset: one vehicle, one
#    mission, one law, still water and one current direction: one markdown row with every
#    score, the targets line and the closed-loop speed line.
"$src/tools/missions-matrix" --build "$2" --vehicles seed004_usv_x --missions test/autonomy/arrive_mission.yaml \
  --laws integral --directions 1 --out "$tmp/matrix" > matrix.out 2>&1 || bad "missions-matrix failed: $(tail -5 matrix.out)"
cat matrix.out
grep -Eq '^\| seed004_usv_x \| arrive_mission \| integral \| - / - \| [0-9.]+ / [0-9.]+ \| [0-9.]+ / [0-9.]+ \| [0-9.]+ \| [0-9.]+ / [0-9.]+ \| [0-9.]+ \|' matrix.out ||
  bad "no matrix row for seed004_usv_x / arrive_mission / integral"
grep -q '^2 runs, ' matrix.out || bad "the matrix did not count 2 runs"
grep -Eq '^Closed loop alone .*[0-9]+x real time' matrix.out || bad "no closed-loop speed line"

# 6. Bad input: exit 2 and a message naming it.
check2() {  # check2 TEXT ARGS...: exit 2 and TEXT in the output
  text="$1"; shift
  out=$("$bin/tiller-run" "$@" 2>&1); rc=$?
  [ $rc -eq 2 ] || bad "tiller-run $* exited $rc (expected 2): $out"
  echo "$out" | grep -qF -- "$text" || bad "tiller-run $*: no '$text' in: $out"
}
check2 "--current-speed: expected a finite number in [0, 5]" config/missions/default.yaml --current-speed 9
check2 "--current-toward-deg: expected together with --current-speed" config/missions/default.yaml --current-toward-deg 30
check2 "no_such.yaml: no such file" config/missions/no_such.yaml
check2 "--set: expected FILE.KEY=VALUE" config/missions/default.yaml --set kp=3
check2 "velocity_pid.yaw.k_eror: unknown key" config/missions/default.yaml --set control.velocity_pid.yaw.k_eror=3
check2 "--sweep: 'speed=1:2:3': unknown name 'speed'" config/missions/default.yaml --sweep speed=1:2:3
check2 "--jobs: expected together with --sweep" config/missions/default.yaml --jobs 3
check2 "give one mission file" --current-speed 0.3
check2 "--guidance: " config/missions/default.yaml --guidance nowhere.yaml
[ $fail -eq 0 ] && echo "run_cli_test: OK"
exit $fail
