#!/bin/sh
# tools/spy under Xvfb, inside the test's own network namespace: lcm-spy must start on Java 17,
# find every Tiller type in the jar, and show a live Tiller channel decoded (screenshot kept in
# the build tree as spy.png). Args: SOURCE_DIR BUILD_DIR
set -eu
src="$1"; build="$2"
out="$build/test-out/spy"; mkdir -p "$out"
n_types=$(ls "$src"/lcmtypes/*.lcm | wc -l)
Xvfb :97 -screen 0 1024x700x24 >"$out/xvfb.log" 2>&1 &
xv=$!
trap 'kill $xv $peer $spy 2>/dev/null || true' EXIT
sleep 1
"$build/tests/runtime_live_peer" "udpm://239.255.76.67:7667?ttl=0" &
peer=$!
DISPLAY=:97 TILLER_TYPES_JAR="$build/tiller-lcmtypes.jar" "$src/tools/spy" >"$out/spy.log" 2>&1 &
spy=$!
for i in $(seq 1 40); do
  grep -q "Found .* LCM types" "$out/spy.log" 2>/dev/null && break
  sleep 0.5
done
sleep 3
DISPLAY=:97 import -window root "$out/spy.png" || true
cat "$out/spy.log"
found=$(sed -n 's/.*Found \([0-9]*\) LCM types.*/\1/p' "$out/spy.log")
# waypoint_t is nested only, but lcm-spy lists it too: every .lcm file is a type.
[ "$found" = "$n_types" ] || { echo "FAIL: lcm-spy found '$found' types, expected $n_types"; exit 1; }
grep -q "Unrecognized option" "$out/spy.log" && { echo "FAIL: Java rejected an lcm-spy option"; exit 1; }
kill -0 $spy 2>/dev/null || { echo "FAIL: lcm-spy exited"; exit 1; }
[ -s "$out/spy.png" ] || { echo "FAIL: no screenshot"; exit 1; }
echo "PASS: lcm-spy decodes $found Tiller types; screenshot $out/spy.png"
