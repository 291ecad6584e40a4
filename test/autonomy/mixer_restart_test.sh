#!/bin/sh
# Issue 12, finding 3, through the real processes: config/launch/sim_usv_mission.yaml (signing on)
# flies the default mission; once the boat is under way the mixer is killed (SIGKILL) and the
# launcher restarts it (restart: on-failure). Nobody acts afterwards, so the vehicle must not
# move again: from 0.3 s after the kill (the ESC's 250 ms command timeout) to the end, every ESC
# output and every thruster command is neutral and TILLER_ARM_STATE never turns armed again (a
# restarted mixer comes back disarmed or waiting; tiller-mission does not repeat its arm request
# or its START). Prints kill -> neutral. Runs under tools/netns-run (CTest). Args: SOURCE_DIR
# BUILD_DIR
set -u
src="$1"; bin="$2/bin"
w=$(mktemp -d)
L=""
trap '[ -n "$L" ] && kill $L 2>/dev/null; wait 2>/dev/null; rm -rf "$w"' EXIT
cd "$src"
PATH="$bin:$PATH" "$bin/tiller-launch" config/launch/sim_usv_mission.yaml \
  --log-file "$w/run.lcmlog" --status-file "$w/status" > "$w/launch.out" 2>&1 &
L=$!
pid_of() { awk -v n="$1" '$1 == n { print $4 }' "$w/status" 2>/dev/null; }
sleep 8   # the mission armed, started and the boat is moving
m1=$(pid_of mixer)
case "$m1" in ''|*[!0-9]*) echo "FAIL: no mixer pid in the status: $(cat "$w/status")"; exit 1 ;; esac
date +%s.%N > "$w/kill"
kill -KILL "$m1"
i=0; m2=$m1
while [ $i -lt 50 ]; do m2=$(pid_of mixer); [ -n "$m2" ] && [ "$m2" != "$m1" ] && [ "$m2" != - ] && break; sleep 0.1; i=$((i + 1)); done
[ "$m2" != "$m1" ] && [ "$m2" != - ] || { echo "FAIL: the launcher did not restart the mixer"; tail -n 20 "$w/launch.out"; exit 1; }
sleep 6   # no operator: nothing may move
kill -INT $L; wait $L; L=""
grep -q "restarting mixer (restart 1)" "$w/launch.out" || { echo "FAIL: no restart line"; tail -n 20 "$w/launch.out"; exit 1; }
for c in TILLER_ESC_OUTPUT TILLER_THRUSTER_COMMAND TILLER_ARM_STATE; do
  "$bin/tiller-log" csv "$w/run.lcmlog" $c > "$w/$c.csv" || exit 1
done
python3 - "$w" "$(cat "$w/kill")" <<'PY'
import csv, sys
w, t_kill = sys.argv[1], float(sys.argv[2])
def rows(c):
    r = list(csv.DictReader(open(f"{w}/{c}.csv")))
    col = next(k for k in r[0] if k in ("utime", "log_utime", "timestamp", "recv_utime"))
    return r, (lambda x: float(x[col]) / 1e6)
esc, te = rows("TILLER_ESC_OUTPUT")
cmd, tc = rows("TILLER_THRUSTER_COMMAND")
arm, ta = rows("TILLER_ARM_STATE")
off = lambda r, p: any(r[k] != "" and abs(float(r[k])) > 0.02 for k in r if k.startswith(p))
armed = lambda r: r["armed"] in ("1", "true", "True")
before = [r for r in esc if t_kill - 2 <= te(r) < t_kill and off(r, "normalized")]
if not before:
    print("FAIL: the boat was not moving before the kill (the test proves nothing)"); sys.exit(1)
first = next((r for r in esc if te(r) >= t_kill and not off(r, "normalized")), None)
moved = [r for r in esc if te(r) >= t_kill + 0.3 and off(r, "normalized")]
pushed = [r for r in cmd if tc(r) >= t_kill and off(r, "command")]
# Armed again after the kill: a disarmed state followed by an armed one.
seen_disarmed, rearmed = False, 0
for r in arm:
    if ta(r) < t_kill: continue
    if not armed(r): seen_disarmed = True
    elif seen_disarmed: rearmed += 1
print(f"mixer killed -> neutral ESC output: {(te(first) - t_kill) * 1000:.0f} ms" if first else "no neutral ESC output")
print(f"after the kill: {len(moved)} ESC outputs off neutral (from +0.3 s), {len(pushed)} thruster "
      f"commands off neutral, {rearmed} armed states after a disarmed one, "
      f"{len([r for r in cmd if tc(r) >= t_kill])} commands from the restarted mixer")
ok = first is not None and not moved and not pushed and rearmed == 0 and any(tc(r) >= t_kill + 0.5 for r in cmd)
sys.exit(0 if ok else 1)
PY
