#!/usr/bin/env python3
"""Writes the recorded joystick streams used by the teleop tests (Linux js interface).

Each file is a sequence of 8-byte `struct js_event {u32 time_ms; s16 value; u8 type; u8 number}`
records, little-endian, exactly what `read()` on /dev/input/jsN returns. Type 0x01 button,
0x02 axis, | 0x80 INIT (the synthetic state the driver sends when the device is opened).

They were made with this script, from the Logitech Extreme 3D Pro's js layout (axes 0 X,
1 Y forward-negative, 2 twist, 3 throttle slider, 4 hat X, 5 hat Y; 12 buttons) and an
Xbox-style pad on xpad (8 axes, triggers resting at -32767; 11 buttons). A real recording is
made the same way with `cat /dev/input/js0 > stream.js` while moving the stick; these are
scripted so that every value in the tests can be computed by hand.

Run: python3 test/data/joystick/make_streams.py   (rewrites the .js files beside it)
Dump: python3 test/data/joystick/make_streams.py --dump FILE
"""
import os
import struct
import sys

BUTTON, AXIS, INIT = 0x01, 0x02, 0x80
HERE = os.path.dirname(os.path.abspath(__file__))


def ev(t_ms, kind, number, value):
    return struct.pack("<IhBB", t_ms, value, kind, number)


def init_block(t_ms, axes, n_buttons, pressed=()):
    out = b""
    for b in range(n_buttons):
        out += ev(t_ms, BUTTON | INIT, b, 1 if b in pressed else 0)
    for a, v in enumerate(axes):
        out += ev(t_ms, AXIS | INIT, a, v)
    return out


# Extreme 3D Pro at rest: stick centred, throttle slider at full back (+32767), hat centred.
E3DP_REST = [0, 0, 0, 32767, 0, 0]


def write(name, data):
    with open(os.path.join(HERE, name), "wb") as f:
        f.write(data)


def main():
    # 1. Plug-in with the stick centred, then known positions (times in ms from plug-in).
    s = init_block(1000, E3DP_REST, 12)
    s += ev(1100, AXIS, 1, -32767)   # full forward
    s += ev(1200, AXIS, 1, -16384)   # half forward
    s += ev(1300, AXIS, 1, 0)
    s += ev(1300, AXIS, 0, 32767)    # full right
    s += ev(1400, AXIS, 0, 0)
    s += ev(1500, AXIS, 1, -32767)   # forward and right together (a corner of the square)
    s += ev(1500, AXIS, 0, 32767)
    s += ev(1600, AXIS, 1, 0)
    s += ev(1600, AXIS, 0, 0)
    write("e3dp_positions.js", s)

    # 2. Plug-in with the stick held full forward: no output until it has been centred.
    s = init_block(1000, [0, -32767, 0, 32767, 0, 0], 12)
    s += ev(1100, AXIS, 1, -20000)
    s += ev(1200, AXIS, 1, 0)        # centred: output may start
    s += ev(1300, AXIS, 1, -32767)   # full forward again: now it counts
    write("e3dp_init_deflected.js", s)

    # 3. Arm button (6) with contact bounce, then a clean disarm (thumb, 1).
    s = init_block(1000, E3DP_REST, 12)
    s += ev(1100, BUTTON, 6, 1)      # bounce: 5 ms pulses, shorter than the 30 ms debounce
    s += ev(1105, BUTTON, 6, 0)
    s += ev(1110, BUTTON, 6, 1)
    s += ev(1115, BUTTON, 6, 0)
    s += ev(1200, BUTTON, 6, 1)      # real press, bouncing once at the start
    s += ev(1203, BUTTON, 6, 0)
    s += ev(1206, BUTTON, 6, 1)      # held from here for 200 ms
    s += ev(1406, BUTTON, 6, 0)
    s += ev(1500, BUTTON, 1, 1)      # disarm
    s += ev(1600, BUTTON, 1, 0)
    write("e3dp_buttons.js", s)

    # 4. Plug-in with the arm button already held (must not arm), then released and pressed.
    s = init_block(1000, E3DP_REST, 12, pressed=(6,))
    s += ev(1200, BUTTON, 6, 0)
    s += ev(1400, BUTTON, 6, 1)
    s += ev(1600, BUTTON, 6, 0)
    write("e3dp_init_button_held.js", s)

    # 5. Xbox-style pad: INIT with triggers released, then RT half, LT full, left stick up.
    s = init_block(1000, [0, 0, -32767, 0, 0, -32767, 0, 0], 11)
    s += ev(1100, AXIS, 5, 0)        # RT half way (normalised 0.5)
    s += ev(1200, AXIS, 5, -32767)
    s += ev(1200, AXIS, 2, 32767)    # LT full
    s += ev(1300, AXIS, 2, -32767)
    s += ev(1300, AXIS, 1, -32767)   # left stick full up
    write("xbox_triggers.js", s)


def dump(path):
    data = open(path, "rb").read()
    for i in range(0, len(data) - 7, 8):
        t, v, kind, n = struct.unpack("<IhBB", data[i:i + 8])
        name = ("button" if kind & 0x7F == BUTTON else "axis") + (" INIT" if kind & INIT else "")
        print(f"{t:8d} ms  {name:12s} {n:3d}  {v:6d}")


if __name__ == "__main__":
    if len(sys.argv) == 3 and sys.argv[1] == "--dump":
        dump(sys.argv[2])
    else:
        main()
