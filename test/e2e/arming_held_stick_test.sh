#!/bin/sh
# Issue 12, finding 1, through the real processes: config/launch/sim_rov_joystick.yaml with a FIFO
# joystick (Extreme 3D Pro layout). Stick forward, arm (refused: stick not neutral), hold 2.5 s:
# every ESC output neutral; centre, arm, push forward: the ESCs move. Then finding 4's second
# half: Ctrl-C (SIGINT) of tiller-teleop while flying gives neutral at once (its last, neutral
# demand), not after the mixer's 0.5 s freshness limit: the first neutral TILLER_THRUSTER_COMMAND
# within 0.2 s of the signal, nothing off neutral after it. Runs under tools/netns-run (CTest).
# Args: SOURCE_DIR BUILD_DIR
set -u
src="$1"; bin="$2/bin"
w=$(mktemp -d); trap 'rm -rf "$w"' EXIT
mkfifo "$w/js"
cd "$src"
PATH="$bin:$PATH" JOYSTICK="$w/js" "$bin/tiller-launch" config/launch/sim_rov_joystick.yaml \
  --log-file "$w/run.lcmlog" --status-file "$w/status" > "$w/launch.out" 2>&1 &
L=$!
sleep 2
python3 - "$w/js" "$w/marks" "$w/status" <<'PY'
import os, signal, struct, sys, time
fifo, marks, status = sys.argv[1], sys.argv[2], sys.argv[3]
plan = [(0, "init"), (1.0, "axis=1,-32767"), (2.0, "btn=6,1"), (2.1, "btn=6,0"), (4.5, "axis=1,0"),
        (4.8, "btn=6,1"), (4.9, "btn=6,0"), (5.5, "axis=1,-32767"), (7.5, "sigint"), (8.5, "end")]
log = open(marks, "w", buffering=1)
fd = os.open(fifo, os.O_WRONLY)
t0 = time.monotonic()
def ev(v, typ, num):
    os.write(fd, struct.pack("<IhBB", int(time.monotonic() * 1000) & 0xFFFFFFFF, v, typ, num))
for t, act in plan:
    d = t0 + t - time.monotonic()
    if d > 0: time.sleep(d)
    if act == "init":
        os.write(fd, b"".join(struct.pack("<IhBB", 0, 0, 0x82, a) for a in range(6)) +
                 b"".join(struct.pack("<IhBB", 0, 0, 0x81, b) for b in range(12)))
    elif act.startswith("axis="):
        n, v = act[5:].split(","); ev(int(v), 0x02, int(n))
    elif act.startswith("btn="):
        n, v = act[4:].split(","); ev(int(v), 0x01, int(n))
    elif act == "sigint":  # Ctrl-C of the teleop alone (the launcher's status names its pid)
        os.kill(next(int(l.split()[3]) for l in open(status) if l.split()[:1] == ["teleop"]),
                signal.SIGINT)
    else:
        break
    log.write(f"{time.time():.6f} {act}\n")
os.close(fd)
PY
sleep 0.5; kill -INT $L; wait $L
[ -s "$w/run.lcmlog" ] || { echo "FAIL: no log: $(tail -n 3 "$w/launch.out")"; exit 1; }
"$bin/tiller-log" csv "$w/run.lcmlog" TILLER_ESC_OUTPUT > "$w/esc.csv" || exit 1
"$bin/tiller-log" csv "$w/run.lcmlog" TILLER_ARM_STATE > "$w/arm.csv" || exit 1
"$bin/tiller-log" csv "$w/run.lcmlog" TILLER_THRUSTER_COMMAND > "$w/cmd.csv" || exit 1
python3 - "$w/esc.csv" "$w/marks" "$w/arm.csv" "$w/cmd.csv" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
marks = {}
for line in open(sys.argv[2]):
    t, a = line.split(" ", 1); marks.setdefault(a.strip(), []).append(float(t))
t_init = marks["init"][0]; t_centre = marks["axis=1,0"][0]; t_push2 = marks["axis=1,-32767"][1]
tcol = next(c for c in rows[0] if c in ("utime", "log_utime", "timestamp", "recv_utime"))
vals = [c for c in rows[0] if c.startswith("value")]
t = lambda r: float(r[tcol]) / 1e6
moving = lambda r: any(abs(float(r[c])) > 100 and abs(float(r[c]) - 1500) > 30 for c in vals if r[c] != "")
early = [r for r in rows if t_init <= t(r) < t_centre + 0.05 and moving(r)]
late = [r for r in rows if t_push2 + 0.3 <= t(r) < t_push2 + 1.8 and moving(r)]
refused = any("pilot demand not neutral" in " ".join(r.values()) for r in csv.DictReader(open(sys.argv[3])))
print(f"{len(early)} ESC outputs off neutral before centring, {len(late)} moving after; refusal on TILLER_ARM_STATE: {refused}")
ok = not early and late and refused
# Ctrl-C of the teleop: the mixer's output neutral at once (the teleop's neutral last word).
t_sig = marks["sigint"][0]
cmds = list(csv.DictReader(open(sys.argv[4])))
ccol = next(c for c in cmds[0] if c in ("utime", "log_utime", "timestamp", "recv_utime"))
cvals = [c for c in cmds[0] if c.startswith("command")]
tc = lambda r: float(r[ccol]) / 1e6
pushing = lambda r: any(r[c] != "" and abs(float(r[c])) > 0.02 for c in cvals)
before = [r for r in cmds if t_sig - 0.5 <= tc(r) < t_sig and pushing(r)]
after = [r for r in cmds if tc(r) >= t_sig]
first = next((r for r in after if not pushing(r)), None)
if not before or first is None:
    print(f"FAIL: no thrust before the teleop's SIGINT ({len(before)}) or no neutral after it"); sys.exit(1)
dt = tc(first) - t_sig
stray = [r for r in after if tc(r) > tc(first) and pushing(r)]
esc_after = [r for r in rows if t(r) >= tc(first) + 0.05 and moving(r)]
print(f"teleop SIGINT -> neutral thruster command: {dt * 1000:.1f} ms; off neutral after it: "
      f"{len(stray)} commands, {len(esc_after)} ESC outputs")
if dt > 0.2 or stray or esc_after:
    print("FAIL: Ctrl-C of the teleop did not give neutral at once"); ok = False
sys.exit(0 if ok else 1)
PY
