#!/usr/bin/env python3
"""tiller-mavlink over a serial link (a telemetry radio), end to end, with a pseudo-terminal pair
standing in for the radio: the real tiller-mavlink (config/mavlink/usv_radio.yaml, its device a
symlink to the pty's slave, as /dev/serial/by-id/... would be) and tiller-sim for telemetry, on
LCM inside tools/netns-run; this script is the ground station on the pty's master, with its own
MAVLink 2 encoder and decoder (header, CRC-X.25 with each message's CRC_EXTRA, SHA-256 signing).

Checks: the port set raw 8N1 at the configured baud, no flow control, modem lines ignored (the
slave left cooked with RTS/CTS on first); a signed HEARTBEAT of a SURFACE_BOAT, autopilot
GENERIC, system 1 component 1; the parameter list; a COMMAND_LONG sent a byte at a time after
line noise (XON/XOFF, CR, LF bytes) answered with COMMAND_ACK and AUTOPILOT_VERSION; position
telemetry from the simulator; a station that stops reading for 3 s while the bridge has much to
say gets whole frames only afterwards (no CRC errors, no bytes between frames); the radio's
other end closed: the bridge alive and idle, then a new radio at the same path: heartbeats and
answers again; SIGINT: exit 0. Prints one line per check; exit 1 on a failure.
Args: SOURCE_DIR BUILD_DIR
"""
import hashlib
import os
import pty
import select
import signal
import struct
import subprocess
import sys
import tempfile
import termios
import threading
import time

SRC, BUILD = sys.argv[1], sys.argv[2]
BIN = os.path.join(BUILD, "bin")

# CRC_EXTRA of every message the bridge sends or this station sends (the official XML's, as
# generated in build/lib/mavlink/gen).
CRC_EXTRA = {0: 50, 1: 124, 21: 159, 22: 220, 24: 24, 30: 39, 33: 104, 36: 222, 42: 28, 44: 221,
             47: 153, 51: 196, 73: 38, 74: 20, 76: 152, 77: 143, 147: 154, 148: 178, 253: 83}
HEARTBEAT, PARAM_REQUEST_LIST, PARAM_VALUE, GLOBAL_POSITION_INT = 0, 21, 22, 33
COMMAND_LONG, COMMAND_ACK, AUTOPILOT_VERSION = 76, 77, 148
MAV_TYPE_SURFACE_BOAT, MAV_TYPE_GCS, MAV_AUTOPILOT_GENERIC, MAV_AUTOPILOT_INVALID = 11, 6, 0, 8
MAV_CMD_REQUEST_AUTOPILOT_CAPABILITIES = 520


def crc_x25(data, crc=0xFFFF):
    for b in data:
        t = b ^ (crc & 0xFF)
        t = (t ^ (t << 4)) & 0xFF
        crc = ((crc >> 8) ^ (t << 8) ^ (t << 3) ^ (t >> 4)) & 0xFFFF
    return crc


class Station:
    """MAVLink 2 both ways on the pty master; frames decoded in a thread."""

    def __init__(self, secret):
        self.secret = secret
        self.lock = threading.Lock()
        self.frames = []  # (t, msgid, sysid, compid, payload, signed)
        self.bad_crc = 0      # frames whose CRC did not match
        self.junk = 0         # bytes outside any frame
        self.seq = 0
        self.ts = 0
        self.paused = False
        self.fd = None
        self.buf = bytearray()
        self.stop = False
        self.thread = threading.Thread(target=self._run, daemon=True)
        self.thread.start()

    def attach(self, fd):
        with self.lock:
            self.fd = fd
            self.buf = bytearray()

    def detach(self):
        with self.lock:
            fd, self.fd = self.fd, None
        return fd

    def _run(self):
        while not self.stop:
            fd = self.fd
            if fd is None or self.paused:
                time.sleep(0.01)
                continue
            try:
                r, _, _ = select.select([fd], [], [], 0.05)
                data = os.read(fd, 65536) if r else b""
            except OSError:
                time.sleep(0.01)
                continue
            if data:
                with self.lock:
                    if self.fd == fd:
                        self.buf += data
                        self._parse()

    def _parse(self):
        b = self.buf
        while True:
            i = b.find(b"\xfd")
            if i < 0:
                self.junk += len(b)
                b.clear()
                return
            self.junk += i
            del b[:i]
            if len(b) < 10:
                return
            n, incompat = b[1], b[2]
            total = 10 + n + 2 + (13 if incompat & 1 else 0)
            if len(b) < total:
                return
            msgid = b[7] | b[8] << 8 | b[9] << 16
            extra = CRC_EXTRA.get(msgid)
            crc = crc_x25(bytes(b[1:10 + n]) + bytes([extra if extra is not None else 0]))
            if extra is None or crc != (b[10 + n] | b[11 + n] << 8):
                self.bad_crc += 1
                del b[:1]  # resynchronise on the next start byte
                continue
            self.frames.append((time.time(), msgid, b[5], b[6], bytes(b[10:10 + n]),
                                bool(incompat & 1)))
            del b[:total]

    def find(self, msgid, since=0.0, pred=lambda p: True):
        with self.lock:
            return [f for f in self.frames if f[1] == msgid and f[0] >= since and pred(f[4])]

    def wait(self, msgid, since, timeout, pred=lambda p: True):
        end = time.time() + timeout
        while time.time() < end:
            f = self.find(msgid, since, pred)
            if f:
                return f[0][0]
            time.sleep(0.02)
        return None

    def frame(self, msgid, payload, sysid=255, compid=190):
        while len(payload) > 1 and payload[-1] == 0:  # MAVLink 2 trims trailing zeros
            payload = payload[:-1]
        self.seq = (self.seq + 1) & 255
        hdr = struct.pack("<BBBBBBBHB", 0xFD, len(payload), 1, 0, self.seq, sysid, compid,
                          msgid & 0xFFFF, msgid >> 16)
        crc = crc_x25(hdr[1:] + payload + bytes([CRC_EXTRA[msgid]]))
        body = hdr + payload + struct.pack("<H", crc)
        self.ts = max(self.ts + 1, int((time.time() - 1420070400) * 1e5))
        tail = bytes([0]) + self.ts.to_bytes(6, "little")
        return body + tail + hashlib.sha256(self.secret + body + tail).digest()[:6]

    def send(self, data, byte_by_byte=False):
        fd = self.fd
        if byte_by_byte:
            for i in range(len(data)):
                os.write(fd, data[i:i + 1])
                time.sleep(0.002)
        else:
            os.write(fd, data)


def heartbeat_of_gcs():
    return struct.pack("<IBBBBB", 0, MAV_TYPE_GCS, MAV_AUTOPILOT_INVALID, 0, 4, 3)


def param_request_list():
    return struct.pack("<BB", 1, 1)


def command_long(cmd, p1=0.0):
    return struct.pack("<7fHBBB", p1, 0, 0, 0, 0, 0, 0, cmd, 1, 1, 0)


def new_radio(link):
    """A fresh pty pair, its slave left cooked with hardware flow control and modem lines on (a
    port a previous program left so), the symlink pointed at it. Returns (master, slave)."""
    m, s = pty.openpty()
    t = termios.tcgetattr(s)
    t[0] |= termios.ICRNL | termios.IXON
    t[1] |= termios.OPOST | termios.ONLCR
    t[2] = (t[2] | termios.CRTSCTS | termios.HUPCL) & ~termios.CLOCAL
    t[3] |= termios.ICANON | termios.ECHO | termios.ISIG
    t[4] = t[5] = termios.B9600
    termios.tcsetattr(s, termios.TCSANOW, t)
    tmp = link + ".new"
    if os.path.lexists(tmp):
        os.unlink(tmp)
    os.symlink(os.ttyname(s), tmp)
    os.replace(tmp, link)
    return m, s


def cpu_seconds(pid):
    with open(f"/proc/{pid}/stat") as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


failed = passed = 0


def check(ok, what):
    global failed, passed
    print(("ok   " if ok else "FAIL ") + what, flush=True)
    if ok:
        passed += 1
    else:
        failed += 1


def main():
    work = tempfile.mkdtemp(prefix="tiller-mavlink-serial-")
    key = os.path.join(work, "sim.key")
    subprocess.run([os.path.join(BIN, "tiller-key"), "new", key], check=True,
                   stdout=subprocess.DEVNULL)
    env = dict(os.environ, TILLER_KEY_FILE=key)
    link = os.path.join(work, "radio")
    cfg = os.path.join(work, "radio.yaml")
    with open(os.path.join(SRC, "config/mavlink/usv_radio.yaml")) as f:
        text = f.read().replace("device: /dev/ttyUSB0", "device: " + link).replace(
            "control_config: config/", "control_config: " + os.path.join(SRC, "config") + "/")
    with open(cfg, "w") as f:
        f.write(text)
    secret = bytes.fromhex(subprocess.run(
        [os.path.join(BIN, "tiller-mavlink"), "--config", cfg, "--print-secret"], env=env,
        check=True, capture_output=True, text=True).stdout.strip())

    m, s = new_radio(link)
    st = Station(secret)
    st.attach(m)
    log = open(os.path.join(work, "procs.log"), "w")
    os.chdir(SRC)
    sim = subprocess.Popen([os.path.join(BIN, "tiller-sim"), "--config", "config/sim/sim.yaml",
                            "--vehicle", "config/vehicles/otter.yaml", "--sensors",
                            "config/sim/sensors/usv.yaml"], env=env, stdout=log, stderr=log)
    bridge = subprocess.Popen([os.path.join(BIN, "tiller-mavlink"), "--config", cfg], env=env,
                              stdout=log, stderr=log)
    try:
        t0 = time.time()
        hb = st.wait(HEARTBEAT, t0, 10)
        check(hb is not None, "a HEARTBEAT over the serial link")
        if hb is None:
            return
        t = termios.tcgetattr(s)
        raw = (not t[0] & (termios.ICRNL | termios.IXON | termios.INLCR | termios.ISTRIP)
               and not t[1] & termios.OPOST
               and not t[3] & (termios.ICANON | termios.ECHO | termios.ISIG | termios.IEXTEN))
        c = t[2]
        check(raw and c & termios.CSIZE == termios.CS8 and not c & termios.PARENB
              and not c & termios.CSTOPB and not c & termios.CRTSCTS and c & termios.CLOCAL
              and c & termios.CREAD and t[4] == t[5] == termios.B57600,
              f"the port raw 8N1 at 57600 baud, no RTS/CTS, modem lines ignored "
              f"(iflag {t[0]:#o} oflag {t[1]:#o} cflag {c:#o} lflag {t[3]:#o} speed {t[4]})")
        os.close(s)
        f = st.find(HEARTBEAT)[0]
        custom, typ, ap, base, status, ver = struct.unpack("<IBBBBB", f[4].ljust(9, b"\0"))
        check(typ == MAV_TYPE_SURFACE_BOAT and ap == MAV_AUTOPILOT_GENERIC and f[2] == 1
              and f[3] == 1 and f[5] and ver == 3,
              f"signed HEARTBEAT: type {typ} (SURFACE_BOAT), autopilot {ap} (GENERIC), "
              f"system {f[2]} component {f[3]}, mavlink {ver}")
        st.send(st.frame(HEARTBEAT, heartbeat_of_gcs()))

        t0 = time.time()
        st.send(st.frame(PARAM_REQUEST_LIST, param_request_list()))
        time.sleep(0.6)
        names = [p[4].ljust(25, b"\0")[8:24].rstrip(b"\0").decode()
                 for p in st.find(PARAM_VALUE, t0)]
        check(len(names) >= 5 and "MAN_GAIN" in names, "parameter list: " + ", ".join(names))

        # Line noise (XOFF, XON, CR, LF, ^C), then a command a byte at a time, as a slow radio
        # delivers it.
        t0 = time.time()
        st.send(b"\x13\x0d\x0a\x03\x11\x00\x55")
        st.send(st.frame(COMMAND_LONG, command_long(MAV_CMD_REQUEST_AUTOPILOT_CAPABILITIES)),
                byte_by_byte=True)
        ack = st.wait(COMMAND_ACK, t0, 3, lambda p: struct.unpack(
            "<HB", p.ljust(3, b"\0")[:3]) == (MAV_CMD_REQUEST_AUTOPILOT_CAPABILITIES, 0))
        ver = st.wait(AUTOPILOT_VERSION, t0, 3)
        check(ack is not None and ver is not None,
              "COMMAND_LONG after line noise, one byte at a time: COMMAND_ACK ACCEPTED and "
              "AUTOPILOT_VERSION")

        gp = st.wait(GLOBAL_POSITION_INT, time.time(), 10)
        check(gp is not None, "GLOBAL_POSITION_INT from tiller-sim over LCM and the serial link")

        # The station stops reading for 3 s while asking for a lot (parameter lists): the bridge
        # must not write part of a frame and then the next one.
        with st.lock:
            bad0, junk0 = st.bad_crc, st.junk
        st.paused = True
        for _ in range(600):
            st.send(st.frame(PARAM_REQUEST_LIST, param_request_list()))
            time.sleep(0.005)
        time.sleep(0.5)
        st.paused = False
        time.sleep(1.5)
        t0 = time.time()
        hb = st.wait(HEARTBEAT, t0, 3)
        with st.lock:
            bad, junk = st.bad_crc - bad0, st.junk - junk0
        check(hb is not None and bad == 0 and junk == 0,
              f"a station that stopped reading: whole frames after it ({bad} CRC errors, "
              f"{junk} bytes between frames), heartbeats go on")

        # The radio's other end goes away (the pty master closed: the slave hangs up).
        os.close(st.detach())
        time.sleep(1.0)
        c0 = cpu_seconds(bridge.pid)
        time.sleep(1.0)
        cpu = cpu_seconds(bridge.pid) - c0
        check(bridge.poll() is None and cpu < 0.3,
              f"the radio gone: the bridge alive, {cpu:.2f} s of CPU in 1 s")

        # A new radio at the same path (a USB radio plugged back in).
        m, s = new_radio(link)
        os.close(s)
        st.attach(m)
        t0 = time.time()
        hb = st.wait(HEARTBEAT, t0, 5)
        check(hb is not None, f"a new radio at the same path: heartbeats again "
              f"({hb - t0:.1f} s)" if hb else "a new radio at the same path: no heartbeat in 5 s")
        if hb is not None:
            t0 = time.time()
            st.send(st.frame(PARAM_REQUEST_LIST, param_request_list()))
            ok = st.wait(PARAM_VALUE, t0, 2)
            check(ok is not None, "and the parameter list answered over it")
    finally:
        st.stop = True
        rc = None
        if bridge.poll() is None:
            bridge.send_signal(signal.SIGINT)
            try:
                rc = bridge.wait(5)
            except subprocess.TimeoutExpired:
                bridge.kill()
                bridge.wait()
        else:
            rc = bridge.returncode
        check(rc == 0, f"SIGINT: the bridge exits {rc}")
        sim.send_signal(signal.SIGINT)
        try:
            sim.wait(5)
        except subprocess.TimeoutExpired:
            sim.kill()
        log.close()
        with open(os.path.join(work, "procs.log")) as f:  # what the bridge said of its port
            for line in f:
                if line.startswith("tiller-mavlink: serial"):
                    print("  " + line.rstrip().replace(work, "WORK"))
        if failed:
            with open(os.path.join(work, "procs.log")) as f:
                print("--- tiller-sim and tiller-mavlink output (last 30 lines):")
                print("".join(f.readlines()[-30:]))
        subprocess.run(["rm", "-rf", work])
    print(f"{passed} passed, {failed} failed")


if __name__ == "__main__":
    main()
    sys.exit(1 if failed else 0)
