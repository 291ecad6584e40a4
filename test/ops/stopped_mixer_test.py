#!/usr/bin/env python3
"""Issue 12, finding 5: a stopped and resumed tiller-mixer never acts on its queued old input.

Usage (CTest runs it inside tools/netns-run, a private network namespace):
    stopped_mixer_test.py SOURCE_DIR BUILD_DIR

Runs config/launch/sim_rov_joystick.yaml (simulator, ESC, mixer, teleop; logged) with a FIFO
joystick. The pilot centres the stick, arms and pushes it forward: the thrusters move. Then the
mixer is stopped (SIGSTOP, by the process id the launcher started) for 4 s while the pilot
goes on: at once, while the mixer's socket still queues what arrives, the stick is centred and
pushed forward again and held there. Resumed (SIGCONT), the mixer finds a centred stick and a
push in its queue, both seconds old; taken at their receive time they would meet the safety
gate's centring condition and move the thrusters. Every node refuses a message whose own utime
is older than its input's freshness limit plus the clock offset bound, so every armed
TILLER_THRUSTER_COMMAND after the resume must be neutral while the stick stays held (the gate
waits for a fresh centring). Prints the time from SIGSTOP to the first neutral ESC output (the
ESC's command timeout) and the mixer's stale-input counters.
"""
import csv
import io
import os
import signal
import struct
import subprocess as sp
import sys
import tempfile
import time

src, build = sys.argv[1], sys.argv[2]
bindir = os.path.join(build, "bin")
work = tempfile.mkdtemp(prefix="tiller-stopped-mixer-")
failures = []


def fail(msg):
    failures.append(msg)
    print("FAIL: " + msg, flush=True)


fifo = os.path.join(work, "js")
os.mkfifo(fifo, 0o600)
js = os.open(fifo, os.O_RDWR | os.O_NONBLOCK)  # keeps the FIFO open: teleop never sees EOF
log = os.path.join(work, "run.lcmlog")
env = dict(os.environ, PATH=bindir + ":" + os.environ["PATH"], JOYSTICK=fifo)
out = open(os.path.join(work, "launch.out"), "w")
# The simulator launch file without message signing: with it, the auth window (1 s) would refuse
# the queued input first (docs/safety.md, "Who may command"), and a run without a key must be
# safe too. Its root is made absolute (the copy lives in the scratch folder).
launch_file = os.path.join(work, "sim_rov_joystick_unsigned.yaml")
with open(os.path.join(src, "config/launch/sim_rov_joystick.yaml")) as f:
    text = "".join(("root: " + src + "\n") if l.startswith("root:") else l for l in f
                   if not l.startswith(("key_file:", "create_key:", "require_signed:")))
# The launcher's heartbeat watchdog (liveness_s, 3 s) would restart a mixer silent for 4 s; this
# test is about the stopped process itself, so the watchdog is off here.
text = text.replace("processes:\n", "liveness_s: 0\nprocesses:\n", 1)
with open(launch_file, "w") as f:
    f.write(text)
launcher = sp.Popen([os.path.join(bindir, "tiller-launch"), launch_file, "--log-file", log],
                    cwd=src, env=env, stdout=out, stderr=sp.STDOUT)
marks = {}


def mark(name):
    marks.setdefault(name, time.time())


def ev(value, typ, num):
    os.write(js, struct.pack("<IhBB", int(time.monotonic() * 1000) & 0xFFFFFFFF, value, typ, num))


def press(b):
    ev(1, 0x01, b)
    time.sleep(0.1)
    ev(0, 0x01, b)


def child(parent, name):
    """The process id of `parent`'s child whose command is `name` (the one we started)."""
    for task in os.listdir(f"/proc/{parent}/task"):
        for pid in open(f"/proc/{parent}/task/{task}/children").read().split():
            try:
                if open(f"/proc/{pid}/comm").read().strip() == name:
                    return int(pid)
            except OSError:
                pass
    return None


ARM = 6  # the Extreme 3D Pro's base button 7 (config/teleop/extreme3dpro_seed000.yaml)
FWD = 1  # its Y axis: -32767 is full forward
STOP_S = 4.0
mixer = None
try:
    time.sleep(3.0)  # every process up, teleop waiting for its device
    os.write(js, b"".join(struct.pack("<IhBB", 0, 0, 0x81, b) for b in range(12)) +
             b"".join(struct.pack("<IhBB", 0, 0, 0x82, a) for a in range(6)))
    time.sleep(1.0)
    press(ARM)
    time.sleep(1.0)
    mark("push")
    ev(-32767, 0x02, FWD)
    time.sleep(1.5)
    mixer = child(launcher.pid, "tiller-mixer")
    if mixer is None:
        raise RuntimeError("tiller-launch has no tiller-mixer child")
    mark("stop")
    os.kill(mixer, signal.SIGSTOP)
    # While the mixer is stopped: centre, then push again and hold (queued in its socket).
    time.sleep(0.05)
    ev(0, 0x02, FWD)
    time.sleep(0.1)
    ev(-32767, 0x02, FWD)
    time.sleep(marks["stop"] + STOP_S - time.time())
    mark("cont")
    os.kill(mixer, signal.SIGCONT)
    time.sleep(2.5)  # stick still held forward
    mark("end")
finally:
    if mixer is not None:
        try:
            os.kill(mixer, signal.SIGCONT)  # never leave it stopped
        except OSError:
            pass
    if launcher.poll() is None:
        launcher.send_signal(signal.SIGINT)
    try:
        launcher.wait(timeout=15)
    except sp.TimeoutExpired:
        launcher.kill()
    os.close(js)


def rows(channel):
    r = sp.run([os.path.join(bindir, "tiller-log"), "csv", log, channel], capture_output=True,
               text=True)
    if r.returncode != 0:
        fail(f"tiller-log csv {channel}: {r.stderr.strip()}")
        return []
    return list(csv.DictReader(io.StringIO(r.stdout)))


def tcol(rs):
    return next(c for c in rs[0] if c in ("log_utime", "recv_utime", "timestamp", "utime"))


def armed(r):
    return r["armed"] in ("1", "true", "True")


cmds, esc, hb = rows("TILLER_THRUSTER_COMMAND"), rows("TILLER_ESC_OUTPUT"), \
    rows("TILLER_HEARTBEAT_MIXER")
if not cmds or not esc:
    fail("no thruster commands or ESC outputs in the log: " +
         open(os.path.join(work, "launch.out")).read()[-400:])
else:
    ct, et = tcol(cmds), tcol(esc)
    cvals = [c for c in cmds[0] if c.startswith("command[")]
    evals = [c for c in esc[0] if c.startswith("value[")]
    t = lambda r, col: float(r[col]) / 1e6
    moving_cmd = lambda r: armed(r) and any(r[c] != "" and abs(float(r[c])) > 1e-6 for c in cvals)
    moving_esc = lambda r: any(r[c] != "" and abs(float(r[c])) > 100 for c in evals)
    before = [r for r in cmds if marks["push"] + 0.5 <= t(r, ct) < marks["stop"] and moving_cmd(r)]
    if not before:
        fail("the thrusters never moved before the stop (arming or the stick did not work)")
    after = [r for r in cmds if marks["cont"] <= t(r, ct) < marks["end"]]
    bad = [r for r in after if moving_cmd(r)]
    if not after:
        fail("the resumed mixer published nothing")
    if bad:
        fail(f"{len(bad)} of {len(after)} thruster commands after SIGCONT are armed and not "
             f"neutral (built from the queued input), the first "
             f"{t(bad[0], ct) - marks['cont']:.3f} s after it")
    neutral = next((r for r in esc if t(r, et) >= marks["stop"] and not moving_esc(r)), None)
    if neutral is None:
        fail("the ESC outputs never went neutral while the mixer was stopped")
        stop_to_neutral = float("nan")
    else:
        stop_to_neutral = t(neutral, et) - marks["stop"]
        if stop_to_neutral > 0.5:
            fail(f"ESC neutral {stop_to_neutral:.3f} s after SIGSTOP (command timeout 250 ms)")
    counters = {}
    for r in hb:
        if t(r, tcol(hb)) < marks["cont"]:
            continue
        n = int(float(r.get("n_counters", "0")))
        for i in range(n):
            name = r.get(f"counter_names[{i}]", "")
            if name.startswith("rejected."):
                counters[name] = r.get(f"counter_values[{i}]")
    print(f"SIGSTOP -> ESC neutral: {stop_to_neutral:.3f} s; after SIGCONT: {len(after)} commands, "
          f"{len(bad)} armed off neutral; mixer refused: "
          f"{', '.join(f'{k} {v}' for k, v in sorted(counters.items())) or 'nothing'}", flush=True)
    if not any(k.endswith(".stale") for k in counters):
        fail("the mixer's heartbeat counted no stale input after SIGCONT")

for f in os.listdir(work):
    os.unlink(os.path.join(work, f))
os.rmdir(work)
if failures:
    print(f"{len(failures)} failure(s)", flush=True)
    sys.exit(1)
print("OK", flush=True)
