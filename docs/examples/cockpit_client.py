#!/usr/bin/env python3
"""A tiller-cockpit client in Python with the standard library only (docs/reference/cockpit-api.md).

    cockpit_client.py [--url ws://127.0.0.1:8088/ws] [--token-file keys/cockpit.token]
                      [--frames N] [--command JSON]

Connects to the cockpit's WebSocket, prints the hello and N state frames (the vehicle's
position, heading and arm state, the processes' health), then, with --command, sends one command
with the token (e.g. '{"type": "mission", "command": "pause"}') and prints the reply.
"""
import argparse
import base64
import json
import os
import socket
import struct
import sys
import urllib.parse


class WebSocket:
    """The client side of RFC 6455, text frames only: enough for the cockpit."""

    def __init__(self, url, timeout=5.0):
        u = urllib.parse.urlparse(url)
        self.sock = socket.create_connection((u.hostname, u.port or 80), timeout=timeout)
        key = base64.b64encode(os.urandom(16)).decode()
        host = f"{u.hostname}:{u.port or 80}"
        self.sock.sendall((f"GET {u.path or '/'} HTTP/1.1\r\nHost: {host}\r\nUpgrade: websocket\r\n"
                           f"Connection: Upgrade\r\nSec-WebSocket-Key: {key}\r\n"
                           "Sec-WebSocket-Version: 13\r\n\r\n").encode())
        head = b""
        while b"\r\n\r\n" not in head:
            chunk = self.sock.recv(1)
            if not chunk:
                raise ConnectionError("closed during the handshake")
            head += chunk
        if b" 101 " not in head.split(b"\r\n")[0]:
            raise ConnectionError("handshake refused: " + head.split(b"\r\n")[0].decode())

    def _read(self, n):
        buf = b""
        while len(buf) < n:
            chunk = self.sock.recv(n - len(buf))
            if not chunk:
                raise ConnectionError("connection closed")
            buf += chunk
        return buf

    def recv(self):
        """The next text message, as a str (pings answered, other frames skipped)."""
        while True:
            b0, b1 = self._read(2)
            n = b1 & 0x7F
            if n == 126:
                n = struct.unpack(">H", self._read(2))[0]
            elif n == 127:
                n = struct.unpack(">Q", self._read(8))[0]
            data = self._read(n)
            op = b0 & 0x0F
            if op == 0x1:
                return data.decode()
            if op == 0x8:
                raise ConnectionError("closed by the server")
            if op == 0x9:
                self._send(0xA, data)

    def _send(self, op, data):
        mask = os.urandom(4)
        n = len(data)
        head = bytes([0x80 | op])
        if n < 126:
            head += bytes([0x80 | n])
        elif n < 65536:
            head += bytes([0x80 | 126]) + struct.pack(">H", n)
        else:
            head += bytes([0x80 | 127]) + struct.pack(">Q", n)
        self.sock.sendall(head + mask + bytes(b ^ mask[i % 4] for i, b in enumerate(data)))

    def send(self, text):
        self._send(0x1, text.encode())


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--url", default="ws://127.0.0.1:8088/ws")
    ap.add_argument("--token-file", default="keys/cockpit.token")
    ap.add_argument("--frames", type=int, default=5)
    ap.add_argument("--command", help="one command as JSON, sent with the token")
    a = ap.parse_args()
    ws = WebSocket(a.url)
    frames = 0
    while frames < a.frames:
        m = json.loads(ws.recv())
        if m["type"] == "hello":
            print("hello: processes", ", ".join(m["processes"]), "at", m["rate_hz"], "Hz")
            continue
        odo = m["msgs"].get("TILLER_ODOMETRY")
        arm = m["msgs"].get("TILLER_ARM_STATE")
        if odo:
            n, e, _ = odo["msg"]["position"]
            print(f"{m['type']}: north {n:.2f} m, east {e:.2f} m, heading "
                  f"{odo['msg']['orientation'][2]:.3f} rad", end="")
        else:
            print(f"{m['type']}: no odometry", end="")
        if arm:
            print(", armed" if arm["msg"]["armed"] else ", disarmed", end="")
        print("; health", " ".join(f"{h['process']}={h['state']}" for h in m["health"]))
        frames += 1
    if a.command:
        cmd = json.loads(a.command)
        cmd["token"] = open(a.token_file).read().strip()
        cmd["id"] = 1
        ws.send(json.dumps(cmd))
        while True:
            m = json.loads(ws.recv())
            if m["type"] == "reply":
                print("reply:", json.dumps(m))
                return 0 if m["ok"] else 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
