#!/usr/bin/env python3
"""Issue 14 item 4 through the real programs: the simulator's NMEA, a real gpsd, tiller-gnss.

Usage (CTest runs it inside tools/netns-run, a private network namespace):
    sim_gpsd_live_test.py SOURCE_DIR BUILD_DIR

Starts tiller-sim with the simulated Otter and the USV's simulated sensors, its GNSS written
only as NMEA to a pseudo-terminal (--gnss-output nmea --nmea-link WORK/gps0, so the simulator
publishes no TILLER_GNSS itself), drifting with a 0.5 m/s current so that the position changes;
then gpsd on that terminal (gpsd -N -n -b, on a private port and control socket, inside this
namespace), tiller-gnss reading that gpsd (config: the private port), and lcm-logger. After
RUN_S s it stops them all and reads the log (tiller-log csv):
  - at least MIN_FIXES TILLER_GNSS fixes, all from tiller-gnss (device: the pseudo-terminal),
    3D, 10 satellites, the receiver's own accuracy (GST) of 2.12 m per horizontal axis (after at
    most 15 early reports gpsd makes before it has seen a whole cycle of sentences);
  - each fix within 5 sigma (15 m) of TILLER_GROUND_TRUTH at its GNSS time (the nearest truth
    sample), the horizontal error RMS between 1 and 5 m (expected sqrt(2) * 2.12 = 3.0 m);
  - the speed over ground within 0.3 m/s of the true speed.
Prints the figures. About 12 s of wall time.
"""
import csv
import io
import math
import os
import signal
import subprocess as sp
import sys
import tempfile
import time

src, build = sys.argv[1], sys.argv[2]
bindir = os.path.join(build, "bin")
RUN_S = 8.0
MIN_FIXES = 20            # 5 Hz for 8 s is 40; gpsd and the links take a few seconds to start
PORT = "29483"            # not gpsd's 2947 (this namespace is private anyway)
LAT0, LON0 = 59.437, 10.6612   # config/sim/sensors/usv.yaml's datum
H_STD = 2.5 / 1.1774      # 2.5 m CEP -> 2.12 m per axis
failures = []


def fail(msg):
    failures.append(msg)
    print("FAIL: " + msg, flush=True)


def ned(lat, lon):
    """North and east (m) of the datum on the WGS84 ellipsoid, to first order: within 100 m of
    the datum the error is below a millimetre."""
    a, f = 6378137.0, 1 / 298.257223563
    e2 = f * (2 - f)
    p = math.radians(LAT0)
    w = math.sqrt(1 - e2 * math.sin(p) ** 2)
    m = a * (1 - e2) / w ** 3   # meridian radius of curvature
    n = a / w                   # prime vertical radius
    return math.radians(lat - LAT0) * m, math.radians(lon - LON0) * n * math.cos(p)


def rows(log, channel):
    out = sp.run([os.path.join(bindir, "tiller-log"), "csv", log, channel], capture_output=True,
                 text=True)
    if out.returncode != 0:
        fail(f"tiller-log csv {log} {channel}: {out.stderr.strip()}")
        return []
    return list(csv.DictReader(io.StringIO(out.stdout)))


def stop(p, name):
    if p is None or p.poll() is not None:
        return
    p.send_signal(signal.SIGTERM)
    try:
        p.wait(timeout=5)
    except sp.TimeoutExpired:
        print(f"{name} needed SIGKILL")
        p.kill()
        p.wait()


work = tempfile.mkdtemp(prefix="tiller-sim-gpsd-")
link = os.path.join(work, "gps0")
log = os.path.join(work, "run.lcmlog")
gnss_cfg = os.path.join(work, "gnss.yaml")
with open(gnss_cfg, "w") as f:
    f.write(f"gpsd_host: 127.0.0.1\ngpsd_port: {PORT}\nstale_after_s: 2.0\n"
            "reconnect_period_s: 0.5\n")
outs = {n: open(os.path.join(work, n + ".out"), "w") for n in ("sim", "gpsd", "gnss", "logger")}
procs = {}
try:
    procs["logger"] = sp.Popen(["lcm-logger", "--quiet", log], stdout=outs["logger"],
                               stderr=sp.STDOUT)
    procs["sim"] = sp.Popen(
        [os.path.join(bindir, "tiller-sim"), "--config", "config/sim/sim.yaml", "--vehicle",
         "config/vehicles/otter.yaml", "--sensors", "config/sim/sensors/usv.yaml",
         "--gnss-output", "nmea", "--nmea-link", link, "--current-speed", "0.5",
         "--current-toward-deg", "45"], cwd=src, stdout=outs["sim"], stderr=sp.STDOUT)
    deadline = time.time() + 10
    while not os.path.exists(link) and time.time() < deadline and procs["sim"].poll() is None:
        time.sleep(0.05)
    if not os.path.exists(link):
        raise RuntimeError(f"tiller-sim made no {link}: " + open(outs["sim"].name).read())
    # -N foreground, -n poll the device without a client, -b read-only (never configure it),
    # -S the port, -F a private control socket (not /run/gpsd.sock).
    procs["gpsd"] = sp.Popen(["gpsd", "-N", "-n", "-b", "-S", PORT, "-F",
                              os.path.join(work, "gpsd.sock"), link],
                             stdout=outs["gpsd"], stderr=sp.STDOUT)
    procs["gnss"] = sp.Popen([os.path.join(bindir, "tiller-gnss"), "--config", gnss_cfg],
                             cwd=src, stdout=outs["gnss"], stderr=sp.STDOUT)
    time.sleep(RUN_S)   # the run's length, not an assertion
    for name, p in procs.items():
        if p.poll() is not None:
            fail(f"{name} exited {p.returncode} during the run: "
                 + open(outs[name].name).read()[-800:])
finally:
    for name in ("gnss", "gpsd", "sim", "logger"):
        stop(procs.get(name), name)
    for f in outs.values():
        f.close()

print("tiller-sim:", open(outs["sim"].name).read().strip().splitlines()[-1:])
fixes = [r for r in rows(log, "TILLER_GNSS") if int(r["fix_type"]) > 0]
# gpsd's first reports of a new device come before it has seen a whole cycle of sentences (no
# time yet, no GST, no GSV): those lead the run and are left out; every later one is checked.
first = next((k for k, r in enumerate(fixes)
              if int(r["gnss_utime"]) > 0 and int(r["accuracy_source"]) == 2), len(fixes))
print(f"{first} early reports of gpsd before its first whole cycle left out")
if first > 15:   # gpsd reports after GGA, GSA and RMC: 15 is the first second at 5 Hz
    fail(f"{first} reports before gpsd's first whole cycle (expected at most 15)")
fixes = fixes[first:]
truth = rows(log, "TILLER_GROUND_TRUTH")
if len(fixes) < MIN_FIXES:
    fail(f"{len(fixes)} fixes through gpsd, expected at least {MIN_FIXES}; tiller-gnss said: "
         + open(outs["gnss"].name).read()[-800:])
if not truth:
    fail("no TILLER_GROUND_TRUTH in the log")
sum2, n, worst, dspeed = 0.0, 0, 0.0, 0.0
tt = [int(r["utime"]) for r in truth]
for f in fixes if truth else []:
    if f["device"] != link and os.path.realpath(f["device"]) != os.path.realpath(link):
        fail(f"a fix from '{f['device']}', not the simulator's terminal {link}")
        break
    if int(f["fix_type"]) != 2 or int(f["satellites"]) != 10:
        fail(f"fix_type {f['fix_type']} (expected 2, 3D), satellites {f['satellites']} (10)")
    if abs(float(f["position_std[0]"]) - H_STD) > 1e-3 or int(f["accuracy_source"]) != 2:
        fail(f"position_std[0] {f['position_std[0]']} from source {f['accuracy_source']}, "
             f"expected {H_STD:.3f} m from the receiver's GST (2)")
    g = int(f["gnss_utime"])
    i = min(range(len(tt)), key=lambda k: abs(tt[k] - g))
    if abs(tt[i] - g) > 60000:
        fail(f"no ground truth within 60 ms of the fix's GNSS time {g} (nearest {tt[i]})")
        continue
    tr = truth[i]
    no, ea = ned(float(f["latitude"]), float(f["longitude"]))
    err = math.hypot(no - float(tr["position[0]"]), ea - float(tr["position[1]"]))
    worst = max(worst, err)
    sum2 += err * err
    n += 1
    true_speed = math.hypot(float(tr["velocity[0]"]), float(tr["velocity[1]"]))  # body u, v
    dspeed = max(dspeed, abs(float(f["speed"]) - true_speed))
if n:
    rms = math.sqrt(sum2 / n)
    epochs = len({f["gnss_utime"] for f in fixes})
    print(f"{n} fixes ({epochs} epochs) through gpsd and tiller-gnss; horizontal error RMS {rms:.2f} m "
          f"(expected 3.0 m), worst {worst:.2f} m; speed over ground within {dspeed:.3f} m/s "
          f"of the truth")
    if worst > 5 * H_STD * math.sqrt(2):
        fail(f"a fix {worst:.2f} m from the true position (5 sigma: {5 * H_STD * 2 ** 0.5:.1f} m)")
    if not 1.0 < rms < 5.0:
        fail(f"horizontal error RMS {rms:.2f} m, expected between 1 and 5 m (3.0 m)")
    if dspeed > 0.3:
        fail(f"speed over ground {dspeed:.3f} m/s off the true speed (at most 0.3)")
if failures:
    print(f"sim_gpsd_live_test: {len(failures)} failure(s); files in {work}")
    sys.exit(1)
print("sim_gpsd_live_test: ok")
