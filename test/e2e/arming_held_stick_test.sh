#!/bin/sh
# Issue 12, finding 1, through the real processes: config/launch/sim_rov_joystick.yaml with a FIFO
# joystick (Extreme 3D Pro layout). Stick forward, arm (refused: stick not neutral), hold 2.5 s:
# every ESC output neutral; centre, arm, push forward: the ESCs move. Runs under tools/netns-run
# (CTest). Args: SOURCE_DIR BUILD_DIR
set -u
src="$1"; bin="$2/bin"
w=$(mktemp -d); trap 'rm -rf "$w"' EXIT
mkfifo "$w/js"
cd "$src"
PATH="$bin:$PATH" JOYSTICK="$w/js" "$bin/tiller-launch" config/launch/sim_rov_joystick.yaml \
  --log-file "$w/run.lcmlog" > "$w/launch.out" 2>&1 &
L=$!
sleep 2
python3 - "$w/js" "$w/marks" <<'PY'
import os, struct, sys, time
fifo, marks = sys.argv[1], sys.argv[2]
plan = [(0, "init"), (1.0, "axis=1,-32767"), (2.0, "btn=6,1"), (2.1, "btn=6,0"), (4.5, "axis=1,0"),
        (4.8, "btn=6,1"), (4.9, "btn=6,0"), (5.5, "axis=1,-32767"), (7.5, "end")]
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
    else:
        break
    log.write(f"{time.time():.6f} {act}\n")
os.close(fd)
PY
sleep 0.5; kill -INT $L; wait $L
[ -s "$w/run.lcmlog" ] || { echo "FAIL: no log: $(tail -n 3 "$w/launch.out")"; exit 1; }
"$bin/tiller-log" csv "$w/run.lcmlog" TILLER_ESC_OUTPUT > "$w/esc.csv" || exit 1
"$bin/tiller-log" csv "$w/run.lcmlog" TILLER_ARM_STATE > "$w/arm.csv" || exit 1
python3 - "$w/esc.csv" "$w/marks" "$w/arm.csv" <<'PY'
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
sys.exit(0 if not early and late and refused else 1)
PY
