#!/bin/sh
# tools/spy under Xvfb, inside the test's own network namespace, with live Tiller processes
# (test/runtime's runtime_live_peer publishes TILLER_HEARTBEAT_* and TILLER_WRENCH_VELOCITY;
# tiller-sim publishes TILLER_ODOMETRY, tiller-mixer TILLER_THRUSTER_COMMAND (neutral, disarmed)
# and TILLER_ALLOCATION_STATUS):
#  1. lcm-spy starts on Java 17 (no "Unrecognized option") and finds every Tiller type in the jar;
#  2. lcm-spy's own channel table (lcm.spy.Spy, read by test/tools/SpyCheck.java in a second
#     lcm-spy window with the classpath tools/spy --print-env gives) lists a TILLER_* channel
#     and decoded its messages with a Tiller class (not only "types found"), and so are the
#     simulator's odometry and the mixer's thruster commands and allocation status;
#  3. a screenshot is kept in the build tree (test-out/spy/spy.png);
#  4. tiller-sim and tiller-mixer sign their messages (a 48-byte trailer after each LCM message,
#     docs/safety.md "Who may command"): lcm-logger's record shows the trailer on their
#     messages, and lcm-spy still decodes every one of them (0 decode errors): LCM's Java
#     decoder reads a message from the front and ignores the trailer.
# Fails (does not skip) when Java (with AWT: a headless JRE cannot open the window), lcm-spy,
# Xvfb or javac is missing. Args: SOURCE_DIR BUILD_DIR
set -u
src="$1"; build="$2"
out="$build/test-out/spy"; mkdir -p "$out"
for tool in java javac lcm-spy Xvfb import; do
  command -v $tool > /dev/null 2>&1 || { echo "FAIL: $tool is not installed (apt-get install default-jdk liblcm-java xvfb imagemagick; see docs/getting-started.md)"; exit 1; }
done
# lcm-spy opens windows: a headless JRE (default-jre-headless alone) has no AWT X11 toolkit and
# lcm-spy dies at its first window. The JRE's lib/ holds libawt_xawt.so when it can open them.
awt="$(dirname "$(readlink -f "$(command -v java)")")/../lib/libawt_xawt.so"
[ -f "$awt" ] || { echo "FAIL: java has no AWT (install default-jre; tools/setup does): $awt missing"; exit 1; }
[ -f "$build/tiller-lcmtypes.jar" ] || { echo "FAIL: $build/tiller-lcmtypes.jar missing (build the lcmtypes jar)"; exit 1; }
n_types=$(ls "$src"/lcmtypes/*.lcm | wc -l)
xv=""; peer=""; spy=""; sim=""; mixer=""; logger=""
trap 'kill $xv $peer $spy $sim $mixer $logger 2>/dev/null || true' EXIT
# Xvfb picks a free display itself (-displayfd) and writes its number once it accepts clients,
# so a display left locked by an earlier run cannot collide with this one.
: > "$out/display"
Xvfb -displayfd 3 -screen 0 1024x700x24 3>"$out/display" >"$out/xvfb.log" 2>&1 &
xv=$!
for i in $(seq 1 40); do
  [ -s "$out/display" ] && break
  sleep 0.25
done
[ -s "$out/display" ] || { cat "$out/xvfb.log"; echo "FAIL: Xvfb did not start"; exit 1; }
DISPLAY=":$(head -n 1 "$out/display")"
export DISPLAY
"$build/bin/tiller-key" new "$out/spy.key" --force > /dev/null || { echo "FAIL: tiller-key new"; exit 1; }
lcm-logger --quiet --lcm-url="udpm://239.255.76.67:7667?ttl=0" "$out/signed.lcmlog" --force > "$out/logger.log" 2>&1 &
logger=$!
"$build/tests/runtime_live_peer" "udpm://239.255.76.67:7667?ttl=0" &
peer=$!
"$build/bin/tiller-sim" --lcm-url "udpm://239.255.76.67:7667?ttl=0" --key-file "$out/spy.key" >"$out/sim.log" 2>&1 &
sim=$!
"$build/bin/tiller-mixer" --config "$src/config/mixer/seed004_usv_x.yaml" \
  --lcm-url "udpm://239.255.76.67:7667?ttl=0" --key-file "$out/spy.key" >"$out/mixer.log" 2>&1 &
mixer=$!
TILLER_TYPES_JAR="$build/tiller-lcmtypes.jar" "$src/tools/spy" >"$out/spy.log" 2>&1 &
spy=$!
for i in $(seq 1 40); do
  grep -q "Found .* LCM types" "$out/spy.log" 2>/dev/null && break
  sleep 0.5
done
fail=0
# 2. The channel table of lcm-spy itself, with tools/spy's environment.
javac -cp "$(sed -n 's/.* -cp \([^ ]*\) .*/\1/p' "$(command -v lcm-spy)")" -d "$out" "$src/test/tools/SpyCheck.java" 2>"$out/javac.log" ||
  { cat "$out/javac.log"; echo "FAIL: SpyCheck.java does not compile"; exit 1; }
spy_cp=$(sed -n 's/.* -cp \([^ ]*\) .*/\1/p' "$(command -v lcm-spy)")
env_lines=$(TILLER_TYPES_JAR="$build/tiller-lcmtypes.jar" "$src/tools/spy" --print-env)
check=$(env "CLASSPATH=$(echo "$env_lines" | sed -n 's/^CLASSPATH=//p')" \
  "JAVA_TOOL_OPTIONS=$(echo "$env_lines" | sed -n 's/^JAVA_TOOL_OPTIONS=//p')" \
  java -cp "$spy_cp:$out" SpyCheck "udpm://239.255.76.67:7667?ttl=0" TILLER_ 15 2>&1); rc=$?
echo "$check" | grep -v "^Picked up JAVA_TOOL_OPTIONS"
[ $rc -eq 0 ] || { echo "FAIL: lcm-spy did not list a decoded TILLER_* channel"; fail=1; }
echo "$check" | grep -Eq "^lcm-spy lists TILLER_[A-Z_]+: decoded as tiller\.[a-z_]+_t, [1-9][0-9]* received, 0 decode errors" ||
  { echo "FAIL: no TILLER_* channel decoded as a tiller.*_t class"; fail=1; }
# The simulator's odometry and the mixer's output, each decoded by lcm-spy with its class.
for pair in TILLER_ODOMETRY:odometry_t TILLER_THRUSTER_COMMAND:thruster_command_t \
            TILLER_ALLOCATION_STATUS:allocation_status_t; do
  ch=${pair%%:*}; cls=${pair#*:}
  c=$(env "CLASSPATH=$(echo "$env_lines" | sed -n 's/^CLASSPATH=//p')" \
    "JAVA_TOOL_OPTIONS=$(echo "$env_lines" | sed -n 's/^JAVA_TOOL_OPTIONS=//p')" \
    java -cp "$spy_cp:$out" SpyCheck "udpm://239.255.76.67:7667?ttl=0" "$ch" 15 2>&1)
  echo "$c" | grep "^lcm-spy lists $ch:"
  echo "$c" | grep -Eq "^lcm-spy lists $ch: decoded as tiller\.$cls, [1-9][0-9]* received, 0 decode errors" ||
    { echo "FAIL: lcm-spy did not decode $ch as tiller.$cls"; cat "$out/sim.log" "$out/mixer.log"; fail=1; }
done
sleep 1
import -window root "$out/spy.png" || true
# 4. The messages lcm-spy decoded were signed: each of these channels' recorded messages ends in
# the trailer's magic (7E 54 53 01) from sender 'sim' or 'mixer'.
kill $logger 2>/dev/null; wait $logger 2>/dev/null; logger=""
signed=$(python3 - "$out/signed.lcmlog" <<'PY'
import struct, sys
data = open(sys.argv[1], 'rb').read()
i, seen = 0, {}
while i + 28 <= len(data):
    sync, _, _, clen, dlen = struct.unpack('>IqqII', data[i:i + 28])
    if sync != 0xEDA1DA01:
        break
    ch = data[i + 28:i + 28 + clen].decode()
    msg = data[i + 28 + clen:i + 28 + clen + dlen]
    i += 28 + clen + dlen
    ok = len(msg) > 48 and msg[-4:] == b'\x7eTS\x01'
    sender = msg[-48:-32].rstrip(b'\0').decode() if ok else '-'
    n_ok, n = seen.get(ch, (0, 0))
    seen[ch] = (n_ok + ok, n + 1)
    seen[ch + ' sender'] = sender
for ch in ('TILLER_ODOMETRY', 'TILLER_THRUSTER_COMMAND', 'TILLER_ALLOCATION_STATUS'):
    n_ok, n = seen.get(ch, (0, 0))
    print('%s: %d of %d signed, sender %s' % (ch, n_ok, n, seen.get(ch + ' sender', '-')))
PY
)
echo "$signed"
for pair in TILLER_ODOMETRY:sim TILLER_THRUSTER_COMMAND:mixer TILLER_ALLOCATION_STATUS:mixer; do
  ch=${pair%%:*}; who=${pair#*:}
  echo "$signed" | grep -Eq "^$ch: ([1-9][0-9]*) of \1 signed, sender $who$" ||
    { echo "FAIL: $ch was not signed by $who in every recorded message"; fail=1; }
done
cat "$out/spy.log"
found=$(sed -n 's/.*Found \([0-9]*\) LCM types.*/\1/p' "$out/spy.log")
# waypoint_t is nested only, but lcm-spy lists it too: every .lcm file is a type.
[ "$found" = "$n_types" ] || { echo "FAIL: lcm-spy found '$found' types, expected $n_types"; fail=1; }
grep -q "Unrecognized option" "$out/spy.log" && { echo "FAIL: Java rejected an lcm-spy option"; fail=1; }
kill -0 $spy 2>/dev/null || { echo "FAIL: lcm-spy (tools/spy) exited"; fail=1; }
[ -s "$out/spy.png" ] || { echo "FAIL: no screenshot"; fail=1; }
[ $fail -eq 0 ] && echo "PASS: lcm-spy finds $found Tiller types and decodes live TILLER_* channels (odometry, thruster commands, allocation status), signed; screenshot $out/spy.png"
exit $fail
