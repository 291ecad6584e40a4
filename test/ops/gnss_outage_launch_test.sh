#!/bin/sh
# Issue 14's 20 s GNSS outage mid-mission through the launched stack on simulated sensors
# (config/launch/sim_usv_sensors.yaml: the simulator's NMEA -> a real gpsd -> tiller-gnss ->
# tiller-nav -> the controllers; tiller-failsafe with config/failsafe/otter_sim.yaml), with
# tiller-sim --gnss-outage 20:20: from 20 s to 40 s its GGA says "no fix" (quality 0), so gpsd
# reports mode 1 and tiller-gnss publishes FIX_NONE. What docs/safety.md says happens, checked from
# the log (tiller-log csv):
#   - gpsd and tiller-gnss carry the outage: no 2D/3D fix for at least 19 s, fixes before and after;
#   - tiller-failsafe's GNSS rule (lost_after_s 5, recover_s 2, action hold): HOLD "GNSS lost" 5 s
#     after the last fix (within 4.5 to 6.5 s), released 2 s after the fixes return (1.5 to 4 s),
#     never a disarm, the ESC armed from the arm to 10 s after the outage (the end of a run disarms);
#   - tiller-nav dead-reckons through it (DEAD_RECKONING set) and is valid again after it;
#   - the mission resumes and completes, every waypoint reached on the estimate (the pose the
#     follower follows), the true final error under 2 m (measured 1.16); the run ends by itself (exit 0).
# The mission is default.yaml with its station keeping cut to 3 s. About 100 s of wall time.
# Args: SOURCE_DIR BUILD_DIR. Runs in a private network namespace (CTest: tools/netns-run).
set -u
src="$1"; bin="$2/bin"
cd "$src"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
sed -e 's/^station_keep_s: .*/station_keep_s: 3/' config/missions/default.yaml > "$tmp/mission.yaml"
sed -e "s|^root: .*|root: $src|" \
    -e 's|--odometry, estimated,|--odometry, estimated, --gnss-outage, "33:20",|' \
    -e '/^  - name: cockpit/,$d' \
    config/launch/sim_usv_sensors.yaml > "$tmp/launch.yaml"
grep -q -- '--gnss-outage, "33:20"' "$tmp/launch.yaml" || { echo "FAIL: could not set the outage in the launch file"; exit 1; }
"$bin/tiller-key" new "$tmp/sim.key" > /dev/null || { echo "FAIL: tiller-key new"; exit 1; }
MISSION="$tmp/mission.yaml" TILLER_KEY_FILE="$tmp/sim.key" TMPDIR="$tmp" timeout 240 \
  "$bin/tiller-launch" "$tmp/launch.yaml" --log-file "$tmp/run.lcmlog" > "$tmp/launch.out" 2>&1
rc=$?
grep -E "^tiller-launch:|FAILED" "$tmp/launch.out" | tail -3
[ $rc -eq 0 ] || { echo "FAIL: the launch exited $rc (the mission did not complete?)"; tail -20 "$tmp/launch.out"; fail=1; }
"$bin/tiller-score" --log "$tmp/run.lcmlog" --mission "$tmp/mission.yaml" > "$tmp/score.out" 2>&1
grep -E "^(waypoints|time to complete|final position err|estimation error|on the estimate)" "$tmp/score.out"
# The follower follows the estimate: every waypoint reached on it. On the truth a waypoint passed
# while the estimate had drifted (up to ~7 m dead-reckoned) can be missed; the end is recovered.
grep -Eq "^on the estimate .*waypoints reached 5, missed 0" "$tmp/score.out" || { echo "FAIL: not every waypoint reached on the estimate"; fail=1; }
awk '/^final position err/ { f = $4 } END { exit !(f != "" && f < 2.0) }' "$tmp/score.out" ||
  { echo "FAIL: the final position error (truth) is not below 2 m: not recovered"; fail=1; }

# The outage as tiller-gnss saw it: the longest stretch without a 2D/3D fix, with fixes around it.
"$bin/tiller-log" csv "$tmp/run.lcmlog" TILLER_GNSS --fields fix_type > "$tmp/gnss.csv"
awk -F, 'NR > 1 { if ($2 >= 1 && $2 != 5) { if (last != "" && $1 - last > gap) { gap = $1 - last; a = last; b = $1 } last = $1; n++ } else nofix++ }
         END { printf "outage at tiller-gnss: last fix %.2f s, first back %.2f s (%.2f s), %d no-fix reports, %d fixes\n", a, b, gap, nofix, n
               print a, b > "/dev/stderr"; exit !(gap >= 19 && gap <= 22 && nofix > 0 && n > 200) }' "$tmp/gnss.csv" 2> "$tmp/gap" ||
  { echo "FAIL: expected a 20 s stretch of no-fix reports through gpsd"; fail=1; }
read -r last back < "$tmp/gap"

# The failsafe: HOLD for GNSS lost about 5 s after the last fix, released about 2 s after the first one back.
"$bin/tiller-log" csv "$tmp/run.lcmlog" TILLER_VEHICLE_STATUS --fields action,reason > "$tmp/status.csv"
awk -F, -v last="$last" -v back="$back" '
  NR > 1 { if (h == "" && $2 == 2 && $3 ~ /^GNSS lost/) h = $1
           if (h != "" && r == "" && $2 == 0) r = $1
           if ($2 == 6) dis++ }
  END { printf "failsafe: HOLD at %s s (%.2f s after the last fix), released at %s s (%.2f s after the first fix back), %d disarm\n", h, h - last, r, r - back, dis
        exit !(h != "" && r != "" && h - last >= 4.5 && h - last <= 6.5 && r - back >= 1.5 && r - back <= 4 && dis == 0) }' "$tmp/status.csv" ||
  { echo "FAIL: the GNSS failsafe did not hold after 5 s and release 2 s after the fixes returned, or disarmed"; fail=1; }
"$bin/tiller-log" csv "$tmp/run.lcmlog" TILLER_ARM_STATE --fields armed > "$tmp/arm.csv"
awk -F, -v back="$back" 'NR > 1 && $1 < back + 10 { if ($2 == 1) armed = 1; else if (armed) drop++ }
         END { printf "ESC: %s, %d disarmed states from the arm to 10 s after the outage\n", armed ? "armed" : "never armed", drop; exit !(armed && drop == 0) }' "$tmp/arm.csv" ||
  { echo "FAIL: the ESC disarmed during the outage"; fail=1; }

# tiller-nav: dead reckoning in the outage, valid position and velocity again after it.
"$bin/tiller-log" csv "$tmp/run.lcmlog" TILLER_ODOMETRY --fields valid > "$tmp/odom.csv"
awk -F, -v back="$back" 'NR > 1 { if (int($2 / 16) % 2) dr++; if ($1 > back + 5) { n++; if ($2 % 4 != 3) bad++ } }
         END { printf "tiller-nav: %d dead-reckoning samples (%.1f s), %d of %d samples from 5 s after the outage not valid\n", dr, dr / 50, bad, n
               exit !(dr / 50 >= 15 && n > 500 && bad == 0) }' "$tmp/odom.csv" ||
  { echo "FAIL: tiller-nav did not dead-reckon through the outage and recover"; fail=1; }

# Back to the receiver smoothly (issue 31 case 6): no step of the published position larger than
# the receiver's own horizontal 1-sigma (the hypot of its position_std, the largest it reported in
# the 10 s after the outage; measured 2.15 m against 3.00 m; before the recovery blending, 7.7 m).
# And no thruster command steps by 1 or more between two commands in those 10 s (half the range:
# not a reversal). Before station keeping's heading_rate_limit_dps it was 1.75, the yaw pair from
# (+0.75, -1) to (-1, +0.75) 1.1 s after the first fix back while the failsafe held: the
# estimate's allowed 0.6 m step took the held point from 1.36 to 0.99 m away, across the
# weathervane's reverse blend, and its heading setpoint 115 deg at once; measured 0.63 after.
# (1.57 in the 10 s before the outage, at a corner: the velocity PID's, not this test's.)
# Columns come in message order: t_s,valid,position[0..1].
"$bin/tiller-log" csv "$tmp/run.lcmlog" TILLER_ODOMETRY --fields position[0],position[1],valid > "$tmp/pos.csv"
"$bin/tiller-log" csv "$tmp/run.lcmlog" TILLER_GNSS --fields fix_type,position_std[0],position_std[1] > "$tmp/std.csv"
"$bin/tiller-log" csv "$tmp/run.lcmlog" TILLER_THRUSTER_COMMAND --fields command[0],command[1] > "$tmp/cmd.csv"
awk -F, -v back="$back" -v last="$last" '
  FNR == 1 { f++; had = 0 }
  f == 1 { if (FNR > 1 && $1 >= back && $1 <= back + 10 && $2 >= 1) { s = sqrt($3 * $3 + $4 * $4); if (s > sigma) sigma = s }; next }
  f == 2 { if (FNR > 1) { ok = $2 % 2 == 1
             if (ok && had) { d = sqrt(($3 - x) ^ 2 + ($4 - y) ^ 2); if (d > step) { step = d; at = $1 } }
             had = ok; x = $3; y = $4 }; next }
  FNR > 1 { if (had) for (i = 2; i <= 3; i++) { d = $i - c[i]; if (d < 0) d = -d
                                                if ($1 >= back && $1 <= back + 10 && d > cstep) { cstep = d; cat = $1 }
                                                if ($1 >= last - 10 && $1 <= last && d > cbefore) cbefore = d }
            had = 1; c[2] = $2; c[3] = $3 }
  END { printf "back from the outage: largest position step %.2f m at %.2f s, the receiver 1-sigma %.2f m; largest thruster command step %.3f in the 10 s after, at %.2f s (%.3f in the 10 s before the outage)\n", step, at, sigma, cstep, cat, cbefore
        exit !(sigma > 0 && step <= sigma && cstep < 1.0) }' "$tmp/std.csv" "$tmp/pos.csv" "$tmp/cmd.csv" ||
  { echo "FAIL: the estimate did not return to the receiver smoothly"; fail=1; }
[ $fail -eq 0 ] && echo "gnss_outage_launch_test: ok"
exit $fail
