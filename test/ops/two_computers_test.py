#!/usr/bin/env python3
"""Two computers: the simulated ROV flown from a topside computer over a link that is cut.

Usage (CTest runs it inside tools/netns-run, a private network namespace):
    two_computers_test.py SOURCE_DIR BUILD_DIR

Inside the private namespace it makes two more, "topside" and "vehicle", each held by a
sleeping process, joined by a veth pair with addresses only on the veths (10.200.0.1/30 and
10.200.0.2/30) and the multicast route via the veth; LCM runs with ttl=1 (the launch files'
lcm_url). The vehicle runs config/launch/vehicle_sim_rov.yaml (simulator, ESC, mixer, logged),
the topside config/launch/topside_seed000_rov.yaml (tiller-teleop reading a FIFO joystick).
The pilot arms with the stick centred and pushes it forward (the vehicle moves); the link is
cut (ip link set down on the topside's veth): every ESC output later than the mixer's
manual-demand freshness limit must be neutral and the ESC must disarm after the longer
pilot-input limit (the mixer's safety.disarm_after_s). The link comes back with the stick still
held: no thrust until the stick is centred and the pilot arms again; then it moves again. Prints the measured
link-cut -> neutral and link-cut -> disarm times. Everything it made is removed at the end.
"""
import csv
import io
import os
import signal
import subprocess as sp
import sys
import tempfile
import time
import struct

src, build = sys.argv[1], sys.argv[2]
bindir = os.path.join(build, "bin")
work = tempfile.mkdtemp(prefix="tiller-two-computers-")
failures = []
procs = []


def fail(msg):
    failures.append(msg)
    print("FAIL: " + msg, flush=True)


def sh(*cmd):
    sp.run(list(cmd), check=True)


def in_ns(holder, *cmd):
    return ["nsenter", "-t", str(holder.pid), "-n", "--"] + list(cmd)


def holder():
    """A process in a new network namespace of its own (the namespace lives while it does)."""
    p = sp.Popen(["unshare", "-n", "sleep", "600"])
    mine = os.readlink("/proc/self/ns/net")
    for _ in range(200):
        try:
            if os.readlink(f"/proc/{p.pid}/ns/net") != mine:
                return p
        except OSError:
            pass
        time.sleep(0.01)
    raise RuntimeError("unshare -n did not start")


def mixer_freshness_s(key, default):
    """freshness.<key> of the vehicle's mixer config, or the mixer's default."""
    for line in open(os.path.join(src, "config/mixer/seed000_rov4.yaml")):
        s = line.split("#")[0]
        if key + ":" in s:
            return float(s.split(key + ":")[1].strip().rstrip("}").split(",")[0])
    return default


# ---- the network: two namespaces, one veth pair, multicast routed over it, nothing else.
top, veh = holder(), holder()
procs += [top, veh]
sh("ip", "link", "add", "tiller-top", "type", "veth", "peer", "name", "tiller-veh")
sh("ip", "link", "set", "tiller-top", "netns", str(top.pid))
sh("ip", "link", "set", "tiller-veh", "netns", str(veh.pid))
for ns, dev, addr in ((top, "tiller-top", "10.200.0.1/30"), (veh, "tiller-veh", "10.200.0.2/30")):
    sh(*in_ns(ns, "ip", "link", "set", "lo", "up"))
    sh(*in_ns(ns, "ip", "addr", "add", addr, "dev", dev))
    sh(*in_ns(ns, "ip", "link", "set", dev, "up", "multicast", "on"))
    sh(*in_ns(ns, "ip", "route", "add", "224.0.0.0/4", "dev", dev))


def link(up):
    sh(*in_ns(top, "ip", "link", "set", "tiller-top", "up" if up else "down"))
    if up:  # a link that went down lost its routes
        for ns, dev in ((top, "tiller-top"), (veh, "tiller-veh")):
            sh(*in_ns(ns, "ip", "route", "replace", "224.0.0.0/4", "dev", dev))


# ---- the two computers' launch files.
fifo = os.path.join(work, "js")
os.mkfifo(fifo, 0o600)
js = os.open(fifo, os.O_RDWR | os.O_NONBLOCK)  # keeps the FIFO open: teleop never sees EOF
env = dict(os.environ, PATH=bindir + ":" + os.environ["PATH"], JOYSTICK=fifo)
vlog, tlog = os.path.join(work, "vehicle.lcmlog"), os.path.join(work, "topside.lcmlog")
vout, tout = open(os.path.join(work, "vehicle.out"), "w"), open(os.path.join(work, "topside.out"), "w")
launch = os.path.join(bindir, "tiller-launch")
vehicle = sp.Popen(in_ns(veh, launch, "config/launch/vehicle_sim_rov.yaml", "--log-file", vlog),
                   cwd=src, env=env, stdout=vout, stderr=sp.STDOUT)
topside = sp.Popen(in_ns(top, launch, "config/launch/topside_seed000_rov.yaml", "--log-file", tlog),
                   cwd=src, env=env, stdout=tout, stderr=sp.STDOUT)
procs += [vehicle, topside]

marks = {}


def mark(name):
    marks.setdefault(name, time.time())


def ev(value, typ, num):
    os.write(js, struct.pack("<IhBB", int(time.monotonic() * 1000) & 0xFFFFFFFF, value, typ, num))


def axis(n, v):
    ev(v, 0x02, n)


def press(b):
    ev(1, 0x01, b)
    time.sleep(0.1)
    ev(0, 0x01, b)


ARM = 6  # the Extreme 3D Pro's base button 7 (config/teleop/extreme3dpro_seed000.yaml)
FWD = 1  # its Y axis: -32767 is full forward
DISARM_AFTER_S = mixer_freshness_s("disarm_after_s", 3.0)  # the longer pilot-input limit
LINK_DOWN_S = DISARM_AFTER_S + 3.0

try:
    time.sleep(3.0)  # every process up, teleop waiting for its device
    os.write(js, b"".join(struct.pack("<IhBB", 0, 0, 0x81, b) for b in range(12)) +
             b"".join(struct.pack("<IhBB", 0, 0, 0x82, a) for a in range(6)))
    time.sleep(1.0)
    press(ARM)
    time.sleep(1.0)
    mark("push")
    axis(FWD, -32767)
    time.sleep(2.0)
    mark("cut")
    link(False)
    time.sleep(LINK_DOWN_S)
    mark("restore")
    link(True)
    time.sleep(2.5)  # stick still held forward
    mark("centre")
    axis(FWD, 0)
    time.sleep(1.0)
    press(ARM)
    time.sleep(1.0)
    mark("push2")
    axis(FWD, -32767)
    time.sleep(2.0)
    mark("end")
finally:
    for p in (topside, vehicle):
        if p.poll() is None:
            p.send_signal(signal.SIGINT)
    for p in (topside, vehicle):
        try:
            p.wait(timeout=15)
        except sp.TimeoutExpired:
            p.kill()
    os.close(js)


def rows(log, channel):
    out = sp.run([os.path.join(bindir, "tiller-log"), "csv", log, channel], capture_output=True,
                 text=True)
    if out.returncode != 0:
        fail(f"tiller-log csv {log} {channel}: {out.stderr.strip()}")
        return []
    return list(csv.DictReader(io.StringIO(out.stdout)))


esc = rows(vlog, "TILLER_ESC_OUTPUT")
arm = rows(vlog, "TILLER_ARM_STATE")
if not esc:
    fail("no TILLER_ESC_OUTPUT in the vehicle's log")
    tcol = None
else:
    tcol = next(c for c in esc[0] if c in ("log_utime", "recv_utime", "timestamp", "utime"))
    vals = [c for c in esc[0] if c.startswith("value")]


def t(r):
    return float(r[tcol]) / 1e6


def moving(r):  # int16 throttle: neutral is 0
    return any(r[c] != "" and abs(float(r[c])) > 100 for c in vals)


def armed(r):
    return r["armed"] in ("1", "true", "True")


measured = {}
if tcol:
    limit = mixer_freshness_s("manual_demand_s", 0.5)
    cut, restore, centre, push2 = marks["cut"], marks["restore"], marks["centre"], marks["push2"]
    flying = [r for r in esc if marks["push"] + 0.3 <= t(r) < cut]
    if not any(moving(r) for r in flying):
        fail("the pilot's stick did not move the vehicle before the cut (no thrust from topside)")
    after_cut = [r for r in esc if cut <= t(r) < restore]
    first_neutral = next((r for r in after_cut if not moving(r)), None)
    if first_neutral is None:
        fail("no neutral ESC output after the link was cut")
    else:
        measured["neutral_s"] = t(first_neutral) - cut
        late = [r for r in after_cut if t(r) >= t(first_neutral) and moving(r)]
        if late:
            fail(f"{len(late)} ESC outputs off neutral after the first neutral one")
        # The limit is the mixer's freshness limit; 0.1 s covers one mixer tick and the ESC's
        # write after the last demand heard.
        if measured["neutral_s"] > limit + 0.1:
            fail(f"neutral {measured['neutral_s']:.3f} s after the cut: limit {limit} s")
    disarm = next((r for r in arm if cut <= float(r[tcol]) / 1e6 < restore and not armed(r)), None)
    if disarm is not None:
        measured["disarm_s"] = float(disarm[tcol]) / 1e6 - cut
        # Disarm after the longer limit, counted from the last input heard or from its loss.
        if measured["disarm_s"] > limit + DISARM_AFTER_S + 0.2:
            fail(f"disarm {measured['disarm_s']:.3f} s after the cut: limit "
                 f"{limit} + {DISARM_AFTER_S} s")
        if measured["disarm_s"] < DISARM_AFTER_S - 0.2:
            fail(f"disarm {measured['disarm_s']:.3f} s after the cut, before the "
                 f"{DISARM_AFTER_S} s limit")
    else:
        fail(f"the ESC did not disarm in the {LINK_DOWN_S} s the link was down")
    held = [r for r in esc if restore <= t(r) < centre + 0.05 and moving(r)]
    if held:
        fail(f"{len(held)} ESC outputs off neutral after the link came back with the stick held")
    again = [r for r in esc if push2 + 0.3 <= t(r) < marks["end"] and moving(r)]
    if not again:
        fail("no thrust after centring, arming again and pushing the stick")
    print(f"link cut -> neutral: {measured.get('neutral_s', float('nan')):.3f} s "
          f"(mixer manual-demand limit {limit} s); link cut -> disarm: "
          f"{measured.get('disarm_s', float('nan')):.3f} s (limit {DISARM_AFTER_S} s); "
          f"held stick after restore: "
          f"{len(held)} outputs off neutral", flush=True)

# ---- clean up: the launchers are gone, the namespaces' holders go, and with them the veths.
for p in (top, veh):
    p.kill()
    p.wait()
time.sleep(0.2)
left = sp.run(["ip", "-o", "link", "show"], capture_output=True, text=True).stdout
if "tiller-top" in left or "tiller-veh" in left:
    fail("a veth was left behind: " + left)
for f in os.listdir(work):
    os.unlink(os.path.join(work, f))
os.rmdir(work)
if failures:
    print(f"{len(failures)} failure(s); launcher output in the run above", flush=True)
    sys.exit(1)
print("OK", flush=True)
