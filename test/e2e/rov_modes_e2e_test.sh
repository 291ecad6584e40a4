#!/bin/sh
# The ROV modes through the real processes: config/launch/sim_rov6_joystick.yaml (tiller-sim,
# tiller-esc, tiller-mixer, tiller-rov-control, tiller-teleop) with a FIFO joystick (Extreme 3D
# Pro layout, config/teleop/extreme3dpro_seed001.yaml), switched by its buttons and by the
# command `tiller-rov-control --mode`. Centre, arm; depth hold (base 11); hat down 2 s: it dives;
# released: it holds the new depth; heading hold (base 12); stabilise and position hold by
# command; manual (base 9). Checks, from the log: each mode in force on TILLER_ARBITRATION after
# its button or command, the dive, the held depth, and the mixer's gate ACTIVE from the start to
# the end (no switch made it wait for the stick again). Runs under tools/netns-run (CTest).
# Args: SOURCE_DIR BUILD_DIR
set -u
src="$1"; bin="$2/bin"
w=$(mktemp -d); trap 'rm -rf "$w"' EXIT
mkfifo "$w/js"
cd "$src"
PATH="$bin:$PATH" JOYSTICK="$w/js" "$bin/tiller-launch" config/launch/sim_rov6_joystick.yaml \
  --log-file "$w/run.lcmlog" --status-file "$w/status" > "$w/launch.out" 2>&1 &
L=$!
sleep 2
python3 - "$w/js" "$w/marks" "$bin" <<'PY'
import os, struct, subprocess, sys, time
fifo, marks, bindir = sys.argv[1], sys.argv[2], sys.argv[3]
plan = [(0, "init"), (1.0, "btn=6,1"), (1.1, "btn=6,0"), (2.0, "btn=10,1"), (2.1, "btn=10,0"),
        (4.0, "axis=5,32767"), (6.0, "axis=5,0"), (9.5, "btn=11,1"), (9.6, "btn=11,0"),
        (10.5, "mode=stabilise"), (11.5, "mode=position_hold"), (12.5, "btn=8,1"),
        (12.6, "btn=8,0"), (13.5, "end")]
log = open(marks, "w", buffering=1)
fd = os.open(fifo, os.O_WRONLY)
t0 = time.monotonic()
def ev(v, typ, num):
    os.write(fd, struct.pack("<IhBB", int(time.monotonic() * 1000) & 0xFFFFFFFF, v, typ, num))
for t, act in plan:
    d = t0 + t - time.monotonic()
    if d > 0: time.sleep(d)
    log.write(f"{time.time():.6f} {act}\n")
    if act == "init":
        os.write(fd, b"".join(struct.pack("<IhBB", 0, 32767 if a == 3 else 0, 0x82, a) for a in range(6)) +
                 b"".join(struct.pack("<IhBB", 0, 0, 0x81, b) for b in range(12)))
    elif act.startswith("axis="):
        n, v = act[5:].split(","); ev(int(v), 0x02, int(n))
    elif act.startswith("btn="):
        n, v = act[4:].split(","); ev(int(v), 0x01, int(n))
    elif act.startswith("mode="):
        subprocess.run([os.path.join(bindir, "tiller-rov-control"), "--mode", act[5:],
                        "--key-file", "keys/sim.key"], check=True, stdout=subprocess.DEVNULL)
    else:
        break
os.close(fd)
PY
sleep 0.3; kill -INT $L; wait $L
[ -s "$w/run.lcmlog" ] || { echo "FAIL: no log: $(tail -n 3 "$w/launch.out")"; exit 1; }
for ch in TILLER_ARBITRATION TILLER_GROUND_TRUTH TILLER_THRUSTER_COMMAND; do
  "$bin/tiller-log" csv "$w/run.lcmlog" $ch > "$w/$ch.csv" || exit 1
done
python3 - "$w" <<'PY'
import csv, sys
w = sys.argv[1]
marks = {}
for line in open(f"{w}/marks"):
    t, a = line.split(" ", 1); marks.setdefault(a.strip(), []).append(float(t))
rd = lambda ch: list(csv.DictReader(open(f"{w}/{ch}.csv")))
t = lambda r: float(r["utime"]) / 1e6
arb, truth, cmd = rd("TILLER_ARBITRATION"), rd("TILLER_GROUND_TRUTH"), rd("TILLER_THRUSTER_COMMAND")
ok = True
def mode_after(t_from, t_to):
    ms = [int(r["mode"]) for r in arb if t_from + 0.3 <= t(r) < t_to]
    return ms[-1] if ms else None
expect = [("btn=10,1", "axis=5,32767", 4, "depth hold (button)"),
          ("btn=11,1", "mode=stabilise", 5, "heading hold (button)"),
          ("mode=stabilise", "mode=position_hold", 3, "stabilise (command)"),
          ("mode=position_hold", "btn=8,1", 8, "position hold (command)"),
          ("btn=8,1", "end", 0, "manual (button)")]
for a, b, m, what in expect:
    got = mode_after(marks[a][0], marks[b][0])
    print(f"{what}: mode in force {got}")
    if got != m: print(f"FAIL: expected {m}"); ok = False
def depth_at(tt):
    return min(truth, key=lambda r: abs(t(r) - tt))
z = lambda tt: float(depth_at(tt)["position[2]"])
d0, d1 = z(marks["axis=5,32767"][0]), z(marks["axis=5,0"][0])
held = [float(r["position[2]"]) for r in truth if marks["axis=5,0"][0] + 1.5 <= t(r) < marks["btn=11,1"][0]]
drift = max(held) - min(held) if held else 99
print(f"hat down 2 s in depth hold: dived {d1 - d0:.2f} m; released: depth held within {drift * 100:.1f} cm "
      f"over {len(held) / 20:.1f} s")
if d1 - d0 < 0.3 or drift > 0.05: print("FAIL: no dive, or the new depth not held"); ok = False
armed = [r for r in cmd if marks["btn=10,1"][0] <= t(r) < marks["end"][0]]
gates = sorted({r["gate"] for r in armed})
print(f"gate over the flight: {gates} (2 = ACTIVE)")
if gates != ["2"]: print("FAIL: the gate left ACTIVE"); ok = False
sys.exit(0 if ok else 1)
PY
