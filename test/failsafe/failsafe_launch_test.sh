#!/bin/sh
# The battery failsafe through the launched stack: config/launch/sim_usv_mission.yaml (the main
# job's launch file, every process real, signed, logged) with the simulated 18 Ah pack starting at
# 17.9 Ah drawn (tiller-sim --battery-used-ah 17.9: open-circuit 13.22 V, below the 14.0 V warning
# and 0.02 Ah above the 13.2 V critical level of config/failsafe/otter_sim.yaml) and that file's
# disarm_after_s cut from 60 s to 4 s. Checks from the log (tiller-log csv):
#   - TILLER_VEHICLE_STATUS: battery warn, then critical with action HOLD, then DISARM 4 s later
#     (within a status period, 0.1 s, plus the failsafe's own tick);
#   - the mission does not complete (TILLER_PATH_PROGRESS complete never 1; the test stops the
#     launch 2 s after the disarm);
#   - after the disarm every TILLER_ESC_OUTPUT is neutral (the ESC's command 0 on each thruster) and
#     the failsafe's heartbeat names the battery.
# Args: SOURCE_DIR BUILD_DIR. Runs in a private network namespace (CTest: tools/netns-run). ~25 s.
set -u
src="$1"; bin="$2/bin"
cd "$src"
tmp=$(mktemp -d)
launcher=""
trap '[ -n "$launcher" ] && kill -KILL "$launcher" 2>/dev/null; rm -rf "$tmp"' EXIT
fail=0
# The launch file and failsafe config, changed only where said above (root: this checkout).
sed -e "s|^root: .*|root: $src|" \
    -e 's|--sensors, config/sim/sensors/usv.yaml,|--sensors, config/sim/sensors/usv.yaml, --battery-used-ah, "17.9",|' \
    -e "s|config/failsafe/otter_sim.yaml|$tmp/failsafe.yaml|" \
    -e '/^  - name: cockpit/,$d' \
    config/launch/sim_usv_mission.yaml > "$tmp/launch.yaml"
grep -q -- '--battery-used-ah, "17.9"' "$tmp/launch.yaml" || { echo "FAIL: could not set the battery in the launch file"; exit 1; }
sed -e 's|^\( *disarm_after_s:\) *60|\1 4|' config/failsafe/otter_sim.yaml > "$tmp/failsafe.yaml"
grep -q 'disarm_after_s: 4' "$tmp/failsafe.yaml" || { echo "FAIL: could not set disarm_after_s"; exit 1; }
"$bin/tiller-key" new "$tmp/sim.key" > /dev/null || { echo "FAIL: tiller-key new"; exit 1; }
TILLER_KEY_FILE="$tmp/sim.key" "$bin/tiller-launch" "$tmp/launch.yaml" --log-file "$tmp/run.lcmlog" > "$tmp/launch.out" 2>&1 &
launcher=$!
# Until the status says DISARM (6), then 2 s more; at most 40 s.
n=0
while [ $n -lt 400 ]; do
  sleep 0.1; n=$((n + 1))
  [ $n -eq 150 ] || [ $n -eq 250 ] || [ $n -eq 400 ] || continue
  "$bin/tiller-log" csv "$tmp/run.lcmlog" TILLER_VEHICLE_STATUS --fields utime,action 2>/dev/null |
    awk -F, 'NR > 1 && $NF == 6 { f = 1 } END { exit !f }' && break
done
sleep 2
kill -INT "$launcher"; wait "$launcher"; launcher=""
"$bin/tiller-log" csv "$tmp/run.lcmlog" TILLER_VEHICLE_STATUS --fields utime,active,latched,action,reason > "$tmp/status.csv" ||
  { echo "FAIL: no TILLER_VEHICLE_STATUS in the log"; cat "$tmp/launch.out"; exit 1; }
head -3 "$tmp/status.csv"
# First times (s) of: warn bit, critical bit with HOLD, DISARM.
awk -F, 'NR > 1 {
    t = $1    # columns: t_s, utime, active, latched, action, reason
    if (w == "" && $3 % 2 == 1) w = t
    if (c == "" && int($3 / 2) % 2 == 1 && $5 == 2) c = t
    if (d == "" && $5 == 6) { d = t; r = $6 }
  }
  END { printf "warn %s critical-hold %s disarm %s (%s)\n", w, c, d, r }' "$tmp/status.csv" | tee "$tmp/times"
read -r _ w _ c _ d _ < "$tmp/times"
[ -n "$w" ] && [ -n "$c" ] && [ -n "$d" ] || { echo "FAIL: expected warn, critical with HOLD, then DISARM"; fail=1; }
if [ $fail -eq 0 ]; then
  awk -v c="$c" -v d="$d" 'BEGIN { x = d - c; printf "disarm %.2f s after critical (disarm_after_s 4)\n", x; exit !(x >= 3.99 && x <= 4.3) }' ||
    { echo "FAIL: the disarm came $c -> $d, expected 4 s after the critical event"; fail=1; }
fi
"$bin/tiller-log" csv "$tmp/run.lcmlog" TILLER_PATH_PROGRESS --fields complete 2>/dev/null |
  awk -F, 'NR > 1 && $1 == 1 { f = 1 } END { exit f }' || { echo "FAIL: the mission completed on a critical battery"; fail=1; }
# ESC outputs after the disarm (+0.1 s): all neutral.
"$bin/tiller-log" csv "$tmp/run.lcmlog" TILLER_ESC_OUTPUT > "$tmp/esc.csv"
[ -n "$d" ] && awk -F, -v d="$d" 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i ~ /^value\[/) v[i] = 1; next }
    $1 > d + 0.2 { ++n; for (i in v) if ($i != 0) ++bad }
    END { printf "%d ESC outputs after the disarm, %d thruster values not neutral\n", n, bad; exit !(n > 0 && bad == 0) }' "$tmp/esc.csv" ||
  { echo "FAIL: ESC output not neutral after the disarm"; fail=1; }
exit $fail
