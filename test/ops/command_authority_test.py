#!/usr/bin/env python3
"""Command authority through the real processes (issue 30): the shipped joystick simulation
(config/launch/sim_rov_joystick.yaml: simulator, ESC, mixer, failsafe, ROV control, teleop on a
FIFO joystick, logged) attacked and shared as docs/safety.md's threat table says.

Usage (CTest runs it inside tools/netns-run, a private network namespace):
    command_authority_test.py SOURCE_DIR BUILD_DIR

  1. A foreign host: a tiller-teleop without the key (its messages unsigned) arms and pushes
     full ahead for 3 s. Every ESC output stays neutral; the ESC counts rejected.auth.unsigned.
  2. Station A (the launch file's teleop) arms with the stick centred and drives ahead.
  3. Station B, a second tiller-teleop with the same key (--station B --name teleop_b), asks to
     arm: refused, and B's status names the station in control within 0.5 s. B pushes full
     astern for 2 s while A holds ahead: no output follows B (no control flip).
  4. B's takeover button: A's status says "control taken by B" within 0.5 s; thrust waits for
     B's centred stick, then follows B; A's stick is refused.
  5. B's joystick re-sends its start-up state (a late INIT at full deflection) while armed and
     moving: neutral from then on, and the vehicle disarms.
Prints, per scenario, the ESC outputs off neutral. Everything it made is removed at the end.
"""
import csv
import io
import os
import shutil
import signal
import struct
import subprocess as sp
import sys
import tempfile
import time

src, build = sys.argv[1], sys.argv[2]
bindir = os.path.join(build, "bin")
work = tempfile.mkdtemp(prefix="tiller-authority-")
failures = []
procs = []
TELEOP_CFG = os.path.join(src, "config/teleop/extreme3dpro_seed000.yaml")
ARM, TAKEOVER, FORWARD, ASTERN = 6, 5, -32767, 32767  # the preset: axis 1 forward is negative


def fail(msg):
    failures.append(msg)
    print("FAIL: " + msg, flush=True)


def start(cmd, name, env):
    out = open(os.path.join(work, name + ".out"), "w")
    p = sp.Popen(cmd, stdout=out, stderr=sp.STDOUT, env=env, cwd=src)
    procs.append(p)
    return p


def stop(p):
    if p.poll() is None:
        p.send_signal(signal.SIGINT)
        try:
            p.wait(10)
        except sp.TimeoutExpired:
            p.kill()
            p.wait()


class Stick:
    """A FIFO joystick (js_event records) in the Extreme 3D Pro's layout, 6 axes, 12 buttons."""

    def __init__(self, name):
        self.path = os.path.join(work, name)
        os.mkfifo(self.path)
        self.fd = None

    def open(self):
        # Blocks until the teleop opens its end (it looks every 0.2 s); the alarm bounds it.
        signal.alarm(20)
        self.fd = os.open(self.path, os.O_WRONLY)
        signal.alarm(0)

    def ev(self, value, typ, num):
        os.write(self.fd, struct.pack("<IhBB", int(time.monotonic() * 1000) & 0xFFFFFFFF,
                                      value, typ, num))

    def init(self):
        os.write(self.fd, b"".join(struct.pack("<IhBB", 0, 0, 0x82, a) for a in range(6)) +
                 b"".join(struct.pack("<IhBB", 0, 0, 0x81, b) for b in range(12)))

    def press(self, button):
        self.ev(1, 0x01, button)
        time.sleep(0.1)
        self.ev(0, 0x01, button)

    def axis(self, value):
        self.ev(value, 0x02, 1)


def table(log, channel):
    r = sp.run([os.path.join(bindir, "tiller-log"), "csv", log, channel], capture_output=True,
               text=True)
    if r.returncode != 0:
        return []
    return list(csv.DictReader(io.StringIO(r.stdout)))


def stamp(row):
    for c in ("utime", "log_utime"):
        if c in row and row[c]:
            return float(row[c]) / 1e6
    return 0.0


def values(row):
    return tuple(int(float(row[c])) for c in row if c.startswith("value") and row[c] != "")


def off_neutral(rows, t0, t1):
    return [r for r in rows if t0 <= stamp(r) < t1 and any(v != 0 for v in values(r))]


def first_status(rows, text, after):
    for r in rows:
        if stamp(r) >= after and text in r.get("status", ""):
            return stamp(r)
    return None


env = dict(os.environ)
env["XDG_CONFIG_HOME"] = os.path.join(work, "xdg")  # the launch file's key is made here
env.pop("TILLER_KEY_FILE", None)
env["PATH"] = bindir + os.pathsep + env.get("PATH", "")
key = os.path.join(work, "xdg", "tiller", "sim.key")
log = os.path.join(work, "run.lcmlog")
a = Stick("jsA")
env["JOYSTICK"] = a.path
marks = {}
try:
    launch = start([os.path.join(bindir, "tiller-launch"), "config/launch/sim_rov_joystick.yaml",
                    "--log-file", log], "launch", env)
    a.open()
    a.init()
    time.sleep(2.5)
    if not os.path.exists(key):
        raise RuntimeError("the launch did not make its key: " +
                           open(os.path.join(work, "launch.out")).read())
    # 1. The foreign host: no key, so its messages are unsigned.
    f = Stick("jsF")
    foreign_env = dict(env)
    foreign_env.pop("TILLER_KEY_FILE", None)
    intruder = start([os.path.join(bindir, "tiller-teleop"), "--config", TELEOP_CFG, "--device",
                      f.path, "--station", "intruder", "--name", "intruder"], "intruder",
                     foreign_env)
    f.open()
    f.init()
    time.sleep(0.8)
    marks["foreign"] = time.time()
    f.press(ARM)
    time.sleep(0.3)
    f.axis(FORWARD)
    time.sleep(3.0)
    marks["foreign_end"] = time.time()
    stop(intruder)
    # 2. Station A arms, centred, and drives ahead.
    a.press(ARM)
    time.sleep(0.8)
    a.axis(-20000)
    time.sleep(1.0)
    marks["a_moving"] = time.time()
    # 3. Station B, with the key: refused, told who holds control; its stick is not followed.
    b = Stick("jsB")
    b_env = dict(env)
    b_env["TILLER_KEY_FILE"] = key
    teleop_b = start([os.path.join(bindir, "tiller-teleop"), "--config", TELEOP_CFG, "--device",
                      b.path, "--station", "B", "--name", "teleop_b"], "teleop_b", b_env)
    b.open()
    b.init()
    time.sleep(1.0)
    marks["b_arm"] = time.time()
    b.press(ARM)
    time.sleep(0.5)
    marks["b_push"] = time.time()
    b.axis(ASTERN)
    time.sleep(2.0)
    marks["b_push_end"] = time.time()
    # 4. B takes over (stick still astern): neutral until B centres, then B drives astern.
    marks["takeover"] = time.time()
    b.press(TAKEOVER)
    time.sleep(1.0)
    marks["b_centre"] = time.time()
    b.axis(0)
    time.sleep(0.5)
    b.axis(ASTERN)
    time.sleep(1.0)
    marks["b_moving"] = time.time()
    # 5. A late INIT on B's joystick at full deflection, while armed and moving.
    marks["late_init"] = time.time()
    os.write(b.fd, struct.pack("<IhBB", 0, FORWARD, 0x82, 1))
    time.sleep(1.5)
    marks["end"] = time.time()
    stop(teleop_b)
    stop(launch)
except Exception as e:  # noqa: BLE001 - a failure to set up is a failure
    fail("setup: %s" % e)
finally:
    for p in procs:
        stop(p)

if not failures:
    esc = table(log, "TILLER_ESC_OUTPUT")
    arm = table(log, "TILLER_ARM_STATE")
    hb_a = table(log, "TILLER_HEARTBEAT_TELEOP")
    hb_b = table(log, "TILLER_HEARTBEAT_TELEOP_B")
    hb_esc = table(log, "TILLER_HEARTBEAT_ESC")
    if not esc:
        fail("no ESC outputs in the log")
    # 1
    n1 = len(off_neutral(esc, marks["foreign"], marks["foreign_end"] + 0.3))
    total1 = len([r for r in esc if marks["foreign"] <= stamp(r) < marks["foreign_end"] + 0.3])
    print("1. foreign host (unsigned): %d of %d ESC outputs off neutral" % (n1, total1))
    if n1:
        fail("the foreign host's commands moved the thrusters (%d outputs)" % n1)
    unsigned = [r for r in hb_esc if stamp(r) > marks["foreign_end"]]
    if not any("rejected.auth.unsigned" in ",".join(r.values()) for r in unsigned):
        fail("the ESC's heartbeat does not count rejected.auth.unsigned")
    # 2
    moving_a = off_neutral(esc, marks["a_moving"] - 0.5, marks["a_moving"])
    if not moving_a:
        fail("station A, armed and centred first, did not move the vehicle")
    a_pattern = values(moving_a[-1]) if moving_a else ()
    # 3
    t_told = first_status(hb_b, "another station in control", marks["b_arm"])
    if t_told is None:
        fail("station B was not told that another station is in control")
    else:
        print("3. B refused and told who holds control after %.3f s" % (t_told - marks["b_arm"]))
        if t_told - marks["b_arm"] > 0.5:
            fail("B was told after %.3f s (> 0.5 s)" % (t_told - marks["b_arm"]))
    window = [r for r in esc if marks["b_push"] + 0.2 <= stamp(r) < marks["b_push_end"]]
    flips = sum(1 for p, q in zip(window, window[1:]) if values(p) != values(q))
    followed_b = [r for r in window if values(r) != a_pattern]
    print("3. B's stick astern while A holds ahead: %d of %d outputs not A's, %d control flips"
          % (len(followed_b), len(window), flips))
    if followed_b or flips:
        fail("station B's stick reached the thrusters (%d outputs, %d flips)"
             % (len(followed_b), flips))
    if not any(stamp(r) > marks["b_arm"] and r.get("controller") not in ("", "B") and
               r.get("armed") in ("1", "true", "True") for r in arm):
        fail("the arm state does not name station A in control")
    # 4
    t_seen = first_status(hb_a, "control taken by B", marks["takeover"])
    if t_seen is None:
        fail("station A did not see the takeover")
    else:
        print("4. A saw the takeover after %.3f s" % (t_seen - marks["takeover"]))
        if t_seen - marks["takeover"] > 0.5:
            fail("A saw the takeover after %.3f s (> 0.5 s)" % (t_seen - marks["takeover"]))
    held = off_neutral(esc, marks["takeover"] + 0.3, marks["b_centre"])
    print("4. after the takeover, B's stick still astern: %d outputs off neutral" % len(held))
    if held:
        fail("thrust after the takeover before B centred its stick")
    moving_b = off_neutral(esc, marks["b_moving"] - 0.5, marks["b_moving"])
    if not moving_b or values(moving_b[-1]) == a_pattern:
        fail("after the takeover B's stick does not drive the vehicle")
    # 5
    late = esc_rows = [r for r in esc if marks["late_init"] + 0.1 <= stamp(r) < marks["end"]]
    n5 = len(off_neutral(esc, marks["late_init"] + 0.1, marks["end"]))
    print("5. late INIT at full deflection while armed: %d of %d outputs off neutral"
          % (n5, len(late)))
    if n5:
        fail("thrust after a late INIT (%d outputs)" % n5)
    if not any(stamp(r) > marks["late_init"] and r.get("armed") in ("0", "false", "False")
               for r in arm):
        fail("the vehicle did not disarm after the late INIT")

if failures:
    for name in ("launch", "teleop_b", "intruder"):
        p = os.path.join(work, name + ".out")
        if os.path.exists(p):
            print("---- %s (last lines)" % name)
            print("".join(open(p).readlines()[-15:]))
shutil.rmtree(work, ignore_errors=True)
print("command_authority_test: %s" % ("FAIL" if failures else "PASS"))
sys.exit(1 if failures else 0)
