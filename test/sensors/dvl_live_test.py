#!/usr/bin/env python3
"""tiller-dvl, the real program, against a fake Water Linked DVL-A50 (a TCP server sending
reports in the protocol's published format, json_v3.1: Water Linked, "DVL protocol",
docs.waterlinked.com).

Usage (CTest runs it inside tools/netns-run, a private network namespace: the fake DVL listens on
that namespace's loopback and LCM stays in it):
    dvl_live_test.py SOURCE_DIR BUILD_DIR

The fake DVL is not there for the first 0.8 s (its port refuses: FAULT "not connected ...",
retried), then accepts, sends 12 velocity reports at 20 Hz (10 with bottom lock, 2 without) mixed
with a malformed line, an invalid report, a dead-reckoning report and a command response, then
closes the connection; it accepts the reconnection tiller-dvl makes (reconnect_s 0.3) and sends 8
more reports with lock, then keeps the connection open and silent so that the heartbeat goes to
FAULT "no velocity report". tiller-dvl runs with a 90 deg yaw mounting and a 0.1 s latency;
lcm-logger logs the bus. Checks (tiller-log csv): exactly 20 TILLER_DVL messages, their velocity
rotated into body FRD (vx 0.1 -> v 0.1), the no-lock ones 0 and altitude -1; the heartbeat's
counters (rejected.line.malformed 1, rejected.line.invalid 1, lines.dead_reckoning 1,
lines.ignored 1, dvl.lock_lost 1, dvl.lock_regained 1, link.connects 2, link.disconnects 1), its
texts (bottom lock, then "no velocity report"); tiller-dvl is still running at the end.
About 5 s of wall time.
"""
import csv
import io
import json
import os
import signal
import socket
import subprocess as sp
import sys
import tempfile
import threading
import time

src, build = sys.argv[1], sys.argv[2]
bindir = os.path.join(build, "bin")
failures = []


def fail(msg):
    failures.append(msg)
    print("FAIL: " + msg, flush=True)


def velocity(i, lock=True):
    """A velocity report as the protocol documents it (json_v3.1), vx = 0.1 + i / 1000."""
    vx = 0.1 + i / 1000.0 if lock else 0.0
    return json.dumps({
        "time": 50.0, "vx": vx, "vy": -0.02 if lock else 0.0, "vz": 0.01 if lock else 0.0,
        "fom": 0.004 if lock else 2.3,
        "covariance": [[1e-4, 0, 0], [0, 4e-4, 0], [0, 0, 9e-4]],
        "altitude": 3.2 if lock else -1.0,
        "transducers": [{"id": k, "velocity": 0.05, "distance": 3.3, "rssi": -30.0,
                         "nsd": -89.0, "beam_valid": lock} for k in range(4)],
        "velocity_valid": lock, "status": 0, "time_of_validity": 1638191471563017 + i,
        "time_of_transmission": 1638191471752336 + i, "format": "json_v3.1",
        "type": "velocity"})


FIRST = ([velocity(i) for i in range(5)]
         + ['{"vx": 0.1, "vy": ',   # malformed (cut short)
            velocity(5, lock=False), velocity(6, lock=False),
            '{"type": "velocity", "vx": 0.1, "vy": 0.0}',  # invalid (no vz, fom, ...)
            json.dumps({"ts": 49056.8, "x": 12.4, "y": 64.1, "z": 1.7, "std": 0.31,
                        "roll": 0.35, "pitch": -1.64, "yaw": 149.28, "type": "position_local",
                        "status": 0, "format": "json_v3.1"}),
            json.dumps({"response_to": "get_config", "success": True, "error_message": "",
                        "result": None, "format": "json_v3.1", "type": "response"})]
         + [velocity(i) for i in range(7, 12)])
SECOND = [velocity(i) for i in range(12, 20)]
EXPECTED = 20  # velocity reports: 12 in the first connection (2 without lock), 8 in the second

server = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
server.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
server.bind(("127.0.0.1", 0))   # bound, not listening yet: the DVL is not there at first
server.settimeout(10)
port = server.getsockname()[1]
done = threading.Event()
accepts = []


def fake_dvl():
    try:
        time.sleep(0.8)   # tiller-dvl starts first: refused, FAULT, retried every 0.3 s
        server.listen(2)
        for n, lines in enumerate((FIRST, SECOND)):
            c, _ = server.accept()
            accepts.append(time.time())
            for line in lines:
                c.sendall((line + "\r\n").encode())   # the A50 ends its lines with CR LF
                time.sleep(0.05)
            if n == 0:
                c.close()   # the DVL goes away (a reboot, a cable)
            else:
                time.sleep(3.0)   # connected and silent: the timeout (1 s) says FAULT, a 1 Hz heartbeat shows it
                server.close()    # no third connection: the counters stay as asserted
                c.close()
    except OSError as e:
        fail(f"fake DVL: {e}")
    finally:
        done.set()


work = tempfile.mkdtemp(prefix="tiller-dvl-")
log = os.path.join(work, "run.lcmlog")
cfg = os.path.join(work, "dvl.yaml")
with open(cfg, "w") as f:
    f.write(f"host: 127.0.0.1\nport: {port}\nmounting: {{roll_deg: 0, pitch_deg: 0, yaw_deg: 90}}\n"
            "latency_s: 0.1\ntimeout_s: 1.0\nmax_fom: 0.1\nreconnect_s: 0.3\n")
outs = {n: open(os.path.join(work, n + ".out"), "w") for n in ("dvl", "logger")}
procs = {}
try:
    procs["logger"] = sp.Popen(["lcm-logger", "--quiet", log], stdout=outs["logger"],
                               stderr=sp.STDOUT)
    time.sleep(0.3)
    procs["dvl"] = sp.Popen([os.path.join(bindir, "tiller-dvl"), "--config", cfg], cwd=src,
                            stdout=outs["dvl"], stderr=sp.STDOUT)
    threading.Thread(target=fake_dvl, daemon=True).start()
    done.wait(timeout=15)
    time.sleep(0.5)
    if procs["dvl"].poll() is not None:
        fail(f"tiller-dvl exited {procs['dvl'].returncode}: " + open(outs["dvl"].name).read())
finally:
    for name in ("dvl", "logger"):
        p = procs.get(name)
        if p is not None and p.poll() is None:
            p.send_signal(signal.SIGTERM)
            try:
                p.wait(timeout=5)
            except sp.TimeoutExpired:
                p.kill()
                p.wait()
    for f in outs.values():
        f.close()
if procs.get("dvl") is not None and procs["dvl"].returncode not in (0, None):
    fail(f"tiller-dvl ended with {procs['dvl'].returncode} on SIGTERM (expected 0)")
said = open(outs["dvl"].name).read()
print("tiller-dvl said:\n  " + "\n  ".join(said.strip().splitlines()))


def rows(channel):
    out = sp.run([os.path.join(bindir, "tiller-log"), "csv", log, channel], capture_output=True,
                 text=True)
    if out.returncode != 0:
        fail(f"tiller-log csv {channel}: {out.stderr.strip()}")
        return []
    return list(csv.DictReader(io.StringIO(out.stdout)))


if len(accepts) != 2:
    fail(f"the fake DVL accepted {len(accepts)} connections (expected 2: tiller-dvl reconnects)")
dvl = rows("TILLER_DVL")
if len(dvl) != EXPECTED:
    fail(f"{len(dvl)} TILLER_DVL messages, expected {EXPECTED}")
locked = [r for r in dvl if int(r["bottom_lock"]) == 1]
unlocked = [r for r in dvl if int(r["bottom_lock"]) == 0]
if len(locked) != 18 or len(unlocked) != 2:
    fail(f"{len(locked)} with bottom lock and {len(unlocked)} without (expected 18 and 2)")
for r in locked:
    u, v, w = (float(r[f"velocity[{k}]"]) for k in range(3))
    # yaw 90: body u = -vy = 0.02, v = vx (0.1 .. 0.119), w = vz
    if abs(u - 0.02) > 1e-9 or not 0.1 - 1e-9 <= v <= 0.12 or abs(w - 0.01) > 1e-9:
        fail(f"velocity [{u}, {v}, {w}] (expected [0.02, 0.1.., 0.01])")
        break
    if abs(float(r["velocity_covariance[0]"]) - 4e-4) > 1e-12 or \
            abs(float(r["velocity_covariance[4]"]) - 1e-4) > 1e-12:
        fail(f"covariance not rotated: {r['velocity_covariance[0]']}, {r['velocity_covariance[4]']}")
        break
    if abs(float(r["altitude"]) - 3.2) > 1e-9 or int(r["beams_valid"]) != 4 or \
            r["sensor"] != f"dvl-a50@127.0.0.1:{port}":
        fail(f"altitude {r['altitude']}, beams {r['beams_valid']}, sensor {r['sensor']}")
        break
for r in unlocked:
    if any(float(r[f"velocity[{k}]"]) != 0 for k in range(3)) or float(r["altitude"]) != -1:
        fail(f"a no-lock message with velocity {r['velocity[0]']} altitude {r['altitude']}")
if dvl:
    r0 = dvl[0]
    keys = list(r0.keys())
    print(f"{len(dvl)} TILLER_DVL messages; first: {dict((k, r0[k]) for k in keys[:6])}")

hb = rows("TILLER_HEARTBEAT_DVL")
if not hb:
    fail("no TILLER_HEARTBEAT_DVL")
else:
    def counters(r):
        n = int(r["n_counters"])
        return {r[f"counter_names[{k}]"]: int(r[f"counter_values[{k}]"]) for k in range(n)}
    last = counters(hb[-1])
    want = {"rejected.line.malformed": 1, "rejected.line.invalid": 1, "lines.dead_reckoning": 1,
            "lines.ignored": 1, "lines.velocity": 20, "dvl.lock_lost": 1,
            "dvl.lock_regained": 1, "link.connects": 2,
            "rejected.velocity.invalid": 0, "dvl.fom_high": 0}
    for k, v in want.items():
        if last.get(k) != v:
            fail(f"heartbeat counter {k} = {last.get(k)} (expected {v})")
    # 1, or 2 when the fake DVL's final close came before the last heartbeat
    if last.get("link.disconnects") not in (1, 2):
        fail(f"heartbeat counter link.disconnects = {last.get('link.disconnects')} (expected 1)")
    statuses = [r["status"] for r in hb]
    print("heartbeat texts:", sorted(set(statuses)))
    if not any(s == "bottom lock, altitude 3.2 m, fom 0.004 m/s" and int(r["state"]) == 0
               for s, r in zip(statuses, hb)):
        fail("no OK heartbeat 'bottom lock, altitude 3.2 m, fom 0.004 m/s'")
    refused = f"not connected to 127.0.0.1:{port}: Connection refused"
    if not any(s == refused and int(r["state"]) == 2 for s, r in zip(statuses, hb)):
        fail(f"no FAULT heartbeat '{refused}' before the DVL was there")
    if not any(s.startswith("no velocity report for ") and int(r["state"]) == 2
               for s, r in zip(statuses, hb)):
        fail("no FAULT heartbeat 'no velocity report for ...' while the DVL was silent")
if "closed by the device" not in said or said.count("connected to the DVL") != 2:
    fail("tiller-dvl did not say the connection closed and came back")
if failures:
    print(f"dvl_live_test: {len(failures)} failure(s); files in {work}")
    sys.exit(1)
print("dvl_live_test: ok")
