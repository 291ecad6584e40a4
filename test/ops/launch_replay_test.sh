#!/bin/sh
# tiller-launch writes LOG.replay.yaml next to every log it starts, and tiller-replay, run from
# another directory (/tmp), replays every replayable process of the run from it without a config
# error, saying which processes it skipped (not replayable). And the logger's rotate + split: a
# run with split_mb 0.05 and rotate 3 leaves exactly FILE.0, FILE.1, FILE.2, each about 50 kB
# (the rest rotated away), readable by tiller-log. In the test's network namespace
# (tools/netns-run); about 15 s. Args: SOURCE_DIR BUILD_DIR
set -u
src="$1"; bin="$2/bin"
tmp=$(mktemp -d)
launcher=""
trap '[ -n "$launcher" ] && kill -KILL "$launcher" 2>/dev/null; rm -rf "$tmp"' EXIT
fail=0
run_for() {  # run_for SECONDS LAUNCH_FILE ARGS...: starts tiller-launch, SIGTERM after SECONDS
  s=$1; shift
  "$bin/tiller-launch" "$@" > "$tmp/out" 2>&1 &
  launcher=$!
  sleep "$s"
  kill -TERM $launcher; wait $launcher; rc=$?; launcher=""
  [ $rc -eq 0 ] || { echo "FAIL: tiller-launch $* exited $rc after SIGTERM"; grep -v '^logger' "$tmp/out" | tail -20; fail=1; }
}

# 1. The sim launch file (the main job's), 8 s of it, then replay from /tmp.
cd "$src"
run_for 8 config/launch/sim_usv_mission.yaml --log-file "$tmp/run.lcmlog" --status-file "$tmp/status"
[ -s "$tmp/run.replay.yaml" ] || { echo "FAIL: no manifest $tmp/run.replay.yaml"; fail=1; }
for p in sim esc mixer velocity-pid station-keep path-follower done mission; do
  grep -q "^  $p:" "$tmp/run.replay.yaml" || { echo "FAIL: manifest lacks $p"; fail=1; }
done
cd /tmp
out=$("$bin/tiller-replay" "$tmp/run.lcmlog" 2>&1); rc=$?
echo "$out" | grep -v '^    '
[ $rc -le 1 ] || { echo "FAIL: tiller-replay exited $rc (a config or usage error)"; fail=1; }
echo "$out" | grep -Eqi "config error|cannot open" && { echo "FAIL: a config error"; fail=1; }
for p in sim esc mixer velocity-pid station-keep path-follower; do
  echo "$out" | grep -q "^$p (config /" || { echo "FAIL: $p not replayed (with an absolute config path)"; fail=1; }
done
echo "$out" | grep -q "^skipped: done (tiller-log: not a replayable process)" || { echo "FAIL: 'done' not reported as skipped"; fail=1; }
echo "$out" | grep -q "^skipped: mission (tiller-mission" || { echo "FAIL: 'mission' not reported as skipped"; fail=1; }
echo "$out" | grep -q "live log: replayed from t=" || { echo "FAIL: not replayed as a live log"; fail=1; }
# Without a manifest, the vehicle-specific processes are skipped with the reason, not an error.
cp "$tmp/run.lcmlog" "$tmp/bare.lcmlog"
out=$("$bin/tiller-replay" "$tmp/bare.lcmlog" 2>&1); rc=$?
[ $rc -le 1 ] || { echo "FAIL: without a manifest tiller-replay exited $rc: $out"; fail=1; }
echo "$out" | grep -q "^skipped: mixer (needs its vehicle's config" || { echo "FAIL: mixer without a manifest not skipped with the reason"; fail=1; }
out=$("$bin/tiller-replay" "$tmp/bare.lcmlog" --process esc 2>&1); rc=$?
[ $rc -eq 2 ] && echo "$out" | grep -q "esc has no default config" || { echo "FAIL: --process esc without config: exit $rc: $out"; fail=1; }
# A manifest naming an unknown process: the file, line and key.
printf 'processes:\n  mixr: config/mixer/otter.yaml\n' > "$tmp/bad.replay.yaml"
out=$("$bin/tiller-replay" "$tmp/run.lcmlog" --configs "$tmp/bad.replay.yaml" 2>&1); rc=$?
[ $rc -eq 2 ] && echo "$out" | grep -q "bad.replay.yaml:2: processes.mixr: expected a process tiller-replay knows" ||
  { echo "FAIL: unknown manifest process: exit $rc: $out"; fail=1; }
# Numeric options are checked first.
out=$("$bin/tiller-replay" "$tmp/run.lcmlog" --tolerance abc 2>&1); rc=$?
[ $rc -eq 2 ] && echo "$out" | grep -q -- "--tolerance: expected a number >= 0, got 'abc'" || { echo "FAIL: --tolerance abc: $rc $out"; fail=1; }
out=$("$bin/tiller-replay" "$tmp/run.lcmlog" --tolerance -5 2>&1); rc=$?
[ $rc -eq 2 ] || { echo "FAIL: --tolerance -5 accepted"; fail=1; }
out=$("$bin/tiller-launch" --status-every abc "$src/config/launch/sim_usv_mission.yaml" --no-log 2>&1); rc=$?
[ $rc -eq 2 ] && echo "$out" | grep -q -- '--status-every: expected a number of seconds' && ! echo "$out" | grep -q "starting" ||
  { echo "FAIL: --status-every abc: exit $rc: $out"; fail=1; }

# 2. Rotate + split: the same stack logged in parts of 50 kB, 3 kept, under a fixed name.
sed -e "s|^root: .*|root: $src|" -e "s|^  dir: logs|  dir: $tmp/rot\n  split_mb: 0.05\n  rotate: 3|" \
  "$src/config/launch/sim_usv_mission.yaml" > "$tmp/rotating.yaml"
grep -q "rotate: 3" "$tmp/rotating.yaml" || { echo "FAIL: could not make the rotating launch file"; fail=1; }
cd "$src"
run_for 6 "$tmp/rotating.yaml" --status-file "$tmp/status2"
ls -l "$tmp/rot"
for k in 0 1 2; do
  f="$tmp/rot/sim-usv-mission.lcmlog.$k"
  [ -s "$f" ] || { echo "FAIL: no $f"; fail=1; continue; }
  size=$(stat -c %s "$f")
  [ "$k" = 0 ] || [ "$size" -ge 40000 ] || { echo "FAIL: $f is $size bytes, a full part is about 50 kB"; fail=1; }
  [ "$size" -le 200000 ] || { echo "FAIL: $f is $size bytes, more than a 50 kB part"; fail=1; }
  # The newest part (.0) holds the last moments (the stack stopping) and may be tiny.
  "$bin/tiller-log" summary "$f" > "$tmp/summary" || { echo "FAIL: tiller-log cannot read $f"; fail=1; }
  [ "$k" = 0 ] || grep -q "TILLER_ODOMETRY" "$tmp/summary" || { echo "FAIL: no odometry in full part $f"; fail=1; }
done
[ -e "$tmp/rot/sim-usv-mission.lcmlog.3" ] && { echo "FAIL: a 4th part was kept (rotate 3)"; fail=1; }
[ -s "$tmp/rot/sim-usv-mission.replay.yaml" ] || { echo "FAIL: no manifest for the rotating log"; fail=1; }
# A part of a rotated log finds the run's manifest (live replay of that part).
out=$(cd /tmp && "$bin/tiller-replay" "$tmp/rot/sim-usv-mission.lcmlog.1" --process path-follower 2>&1); rc=$?
[ $rc -le 1 ] && echo "$out" | grep -q "live log: replayed from" ||
  { echo "FAIL: replaying a rotated part did not use the run's manifest: exit $rc: $out"; fail=1; }
[ $fail -eq 0 ] && echo "launch_replay_test: ok"
exit $fail
