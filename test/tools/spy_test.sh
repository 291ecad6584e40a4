#!/bin/sh
# tools/spy under Xvfb, inside the test's own network namespace, with a live Tiller peer
# (test/runtime's runtime_live_peer publishes TILLER_HEARTBEAT_* and TILLER_WRENCH_VELOCITY):
#  1. lcm-spy starts on Java 17 (no "Unrecognized option") and finds every Tiller type in the jar;
#  2. lcm-spy's own channel table (lcm.spy.Spy, read by test/tools/SpyCheck.java in a second
#     lcm-spy window with the classpath tools/spy --print-env gives) lists a TILLER_* channel
#     and decoded its messages with a Tiller class (not only "types found");
#  3. a screenshot is kept in the build tree (test-out/spy/spy.png).
# Fails (does not skip) when Java, lcm-spy, Xvfb or javac is missing. Args: SOURCE_DIR BUILD_DIR
set -u
src="$1"; build="$2"
out="$build/test-out/spy"; mkdir -p "$out"
for tool in java javac lcm-spy Xvfb import; do
  command -v $tool > /dev/null 2>&1 || { echo "FAIL: $tool is not installed (apt-get install default-jdk liblcm-java xvfb imagemagick; see README)"; exit 1; }
done
[ -f "$build/tiller-lcmtypes.jar" ] || { echo "FAIL: $build/tiller-lcmtypes.jar missing (build the lcmtypes jar)"; exit 1; }
n_types=$(ls "$src"/lcmtypes/*.lcm | wc -l)
xv=""; peer=""; spy=""
trap 'kill $xv $peer $spy 2>/dev/null || true' EXIT
Xvfb :97 -screen 0 1024x700x24 >"$out/xvfb.log" 2>&1 &
xv=$!
sleep 1
"$build/tests/runtime_live_peer" "udpm://239.255.76.67:7667?ttl=0" &
peer=$!
DISPLAY=:97 TILLER_TYPES_JAR="$build/tiller-lcmtypes.jar" "$src/tools/spy" >"$out/spy.log" 2>&1 &
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
check=$(env DISPLAY=:97 "CLASSPATH=$(echo "$env_lines" | sed -n 's/^CLASSPATH=//p')" \
  "JAVA_TOOL_OPTIONS=$(echo "$env_lines" | sed -n 's/^JAVA_TOOL_OPTIONS=//p')" \
  java -cp "$spy_cp:$out" SpyCheck "udpm://239.255.76.67:7667?ttl=0" TILLER_ 15 2>&1); rc=$?
echo "$check" | grep -v "^Picked up JAVA_TOOL_OPTIONS"
[ $rc -eq 0 ] || { echo "FAIL: lcm-spy did not list a decoded TILLER_* channel"; fail=1; }
echo "$check" | grep -Eq "^lcm-spy lists TILLER_[A-Z_]+: decoded as tiller\.[a-z_]+_t, [1-9][0-9]* received, 0 decode errors" ||
  { echo "FAIL: no TILLER_* channel decoded as a tiller.*_t class"; fail=1; }
sleep 1
DISPLAY=:97 import -window root "$out/spy.png" || true
cat "$out/spy.log"
found=$(sed -n 's/.*Found \([0-9]*\) LCM types.*/\1/p' "$out/spy.log")
# waypoint_t is nested only, but lcm-spy lists it too: every .lcm file is a type.
[ "$found" = "$n_types" ] || { echo "FAIL: lcm-spy found '$found' types, expected $n_types"; fail=1; }
grep -q "Unrecognized option" "$out/spy.log" && { echo "FAIL: Java rejected an lcm-spy option"; fail=1; }
kill -0 $spy 2>/dev/null || { echo "FAIL: lcm-spy (tools/spy) exited"; fail=1; }
[ -s "$out/spy.png" ] || { echo "FAIL: no screenshot"; fail=1; }
[ $fail -eq 0 ] && echo "PASS: lcm-spy finds $found Tiller types and decodes a live TILLER_* channel; screenshot $out/spy.png"
exit $fail
