#!/usr/bin/env python3
# Runs the official MAVLink generator (pymavlink/generator, vendored here unchanged) for C,
# MAVLink 2, on one XML file and its includes: mavgen-c.py OUTPUT_DIR XML. The build calls it
# (lib/mavlink/CMakeLists.txt); python3's standard library is all it needs (XML validation,
# which would need lxml, is off). Run it with PYTHONHASHSEED=0: the generated XML hash then
# does not change from one build to the next. See README.md for where the files come from.
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pymavlink.generator import mavgen  # noqa: E402


class Options:
    language = "C"
    wire_protocol = "2.0"
    validate = False
    error_limit = 200
    strict_units = False


if len(sys.argv) != 3:
    sys.exit("usage: mavgen-c.py OUTPUT_DIR XML")
opts = Options()
opts.output = sys.argv[1]
sys.exit(0 if mavgen.mavgen(opts, [sys.argv[2]]) else 1)
