#!/bin/sh
# The real launch files (both ROVs, the USV), started as on the vehicle but without hardware:
# ESC_CONFIG points tiller-esc at the dry-run configs (they print the bus bytes instead of writing them) and
# JOYSTICK at a FIFO (unused: the pilot's teleop runs on the topside computer,
# topside_<vehicle>_rov.yaml). In the test's network namespace (tools/netns-run). Checks that
# every process comes up (logger, esc, mixer, failsafe, nav and the sensor drivers running, the
# drivers' heartbeats naming the missing bus and address or GPIO line; no teleop on the vehicle
# computer),
# the dry run prints the neutral writes (seed 000: throttle 0 to each BlueESC; seed 001: 1500 us,
# 0x0133 counts, on each PCA9685 channel), the log rotates under its fixed name with a replay
# manifest, and SIGTERM stops everything (exit 0, no process of the run left). The vehicle key
# comes from TILLER_KEY_FILE (a fresh one, made with tiller-key), and every process says it
# signs and refuses unsigned input; without a key file the launch stops at once (exit 2).
# Args: SOURCE_DIR BUILD_DIR
set -u
src="$1"; bin="$2/bin"
cd "$src"
tmp=$(mktemp -d)
launcher=""
trap '[ -n "$launcher" ] && kill -KILL "$launcher" 2>/dev/null; rm -rf "$tmp"' EXIT
fail=0
"$bin/tiller-key" new "$tmp/vehicle.key" > /dev/null || { echo "FAIL: tiller-key new"; exit 1; }
TILLER_KEY_FILE="$tmp/vehicle.key"
export TILLER_KEY_FILE

# wait_for SECONDS COMMAND...: polls until COMMAND succeeds (a deadline, not a timing assertion).
wait_for() {
  n=$(( $1 * 10 )); shift
  while [ $n -gt 0 ]; do "$@" && return 0; sleep 0.1; n=$((n - 1)); done
  "$@"
}
all_running() {
  "$bin/tiller-launch" status "$1" --status-file "$2" > "$2.now" 2>/dev/null || return 1
  for p in $expect; do
    grep -Eq "^$p +[a-z]+ +running" "$2.now" || return 1
  done
}
# Every expected process (but the logger) has published a heartbeat (hb_s is a number).
all_beating() {
  all_running "$1" "$2" || return 1
  for p in $expect; do
    [ $p = logger ] && continue
    awk -v p=$p '$1 == p && $6 ~ /^[0-9.]+$/ { ok = 1 } END { exit !ok }' "$2.now" || return 1
  done
}

# No key (the default /etc/tiller/vehicle.key is not there): refused before anything starts.
out=$(TILLER_KEY_FILE="$tmp/none.key" "$bin/tiller-launch" config/launch/real_seed000_rov.yaml --no-log 2>&1); rc=$?
[ $rc -eq 2 ] && echo "$out" | grep -q "key file '$tmp/none.key': No such file" ||
  { echo "FAIL: a missing vehicle key gave exit $rc: $out"; fail=1; }

for vehicle in seed000 seed001 otter; do
  if [ $vehicle = otter ]; then
    file=config/launch/real_usv.yaml
    expect="logger esc mixer failsafe nav gnss imu power velocity-pid station-keep path-follower"
    beats="GNSS:cannot~connect~to~gpsd~at~127.0.0.1:2947 IMU:bno055~on~/dev/i2c-1~at~0x28 POWER:ina226~on~/dev/i2c-1~at~0x41 NAV: FAILSAFE:"
  else
    file=config/launch/real_${vehicle}_rov.yaml
    expect="logger esc mixer failsafe nav pressure imu leak power"
    beats="PRESSURE:ms5837-30ba~on~/dev/i2c-1~at~0x76 IMU:bno055~on~/dev/i2c-1~at~0x28 POWER:ina226~on~/dev/i2c-1~at~0x41 LEAK:probe~main_tube~(gpiochip0~line~27 NAV: FAILSAFE:"
  fi
  name=$(sed -n 's/^name: //p' "$file")
  dir="$tmp/$vehicle"; mkdir -p "$dir"
  if grep -q "command: tiller-teleop" "$file"; then
    echo "FAIL: $file runs tiller-teleop on the vehicle computer (it belongs topside)"; fail=1
  fi
  mkfifo "$dir/js"
  exec 3<>"$dir/js"          # keep the FIFO open: teleop sees a joystick that sends nothing
  ESC_CONFIG=config/esc/${vehicle}_dry_run.yaml JOYSTICK="$dir/js" \
    "$bin/tiller-launch" "$file" --log-dir "$dir/logs" --status-file "$dir/status" > "$dir/out" 2>&1 &
  launcher=$!
  if ! wait_for 15 all_beating "$file" "$dir/status"; then
    echo "FAIL: $file: not every process running with a heartbeat:"; cat "$dir/status.now" 2>/dev/null; fail=1
  fi
  grep -q "signing: key $tmp/vehicle.key, unsigned input refused" "$dir/out" ||
    { echo "FAIL: $file: the launcher does not say it signs and refuses unsigned input"; fail=1; }
  # Neutral bus writes from the dry run.
  if [ $vehicle = seed000 ]; then
    for a in 29 2a 2b 2c; do
      wait_for 5 grep -q "^esc .*| dry-run .* 0x$a write 00 00 00" "$dir/out" ||
        { echo "FAIL: $file: no neutral write (00 00 00) to ESC 0x$a"; fail=1; }
    done
  else
    n=6; [ $vehicle = otter ] && n=2
    wait_for 5 sh -c "[ \$(grep -c '^esc .*| dry-run .* 0x40 write [0-9a-f][0-9a-f] 00 00 33 01' '$dir/out') -ge $n ]" ||
      { echo "FAIL: $file: fewer than $n neutral PCA9685 writes (1500 us = 00 00 33 01)"; fail=1; }
  fi
  pids=$(awk 'NR > 2 && $4 ~ /^[0-9]+$/ { print $4 }' "$dir/status.now" 2>/dev/null)
  kill -TERM $launcher
  wait $launcher; rc=$?
  launcher=""
  exec 3>&-
  [ $rc -eq 0 ] || { echo "FAIL: $file: tiller-launch exited $rc after SIGTERM"; fail=1; }
  for p in $pids; do
    if kill -0 "$p" 2>/dev/null && ! grep -q '^State:.*zombie' "/proc/$p/status" 2>/dev/null; then
      echo "FAIL: $file: process $p still alive after the launcher stopped"; fail=1
    fi
  done
  [ -n "$pids" ] || { echo "FAIL: $file: no pids in the status table"; fail=1; }
  grep -q "the run ended\|stopped\|SIGTERM" "$dir/out" || { echo "FAIL: $file: no stop reason printed"; fail=1; }
  # Bounded logging: rotate under a fixed name (the newest is .0), with its replay manifest.
  [ -s "$dir/logs/$name.lcmlog.0" ] || { echo "FAIL: $file: no rotated log $dir/logs/$name.lcmlog.0"; ls "$dir/logs"; fail=1; }
  grep -q "program: \"tiller-esc\"" "$dir/logs/$name.replay.yaml" 2>/dev/null ||
    { echo "FAIL: $file: no replay manifest next to the log"; fail=1; }
  # No hardware here: each sensor driver still runs (checked above) and its heartbeat names the
  # bus and address, or the GPIO chip and line; tiller-nav and tiller-failsafe report too.
  for hb in $beats; do
    ch=${hb%%:*}; want=$(echo "${hb#*:}" | tr '~' ' ')  # ~: a space
    last=$("$bin/tiller-log" csv "$dir/logs/$name.lcmlog.0" "TILLER_HEARTBEAT_$ch" --fields state,status 2>/dev/null | tail -1)
    echo "$file: TILLER_HEARTBEAT_$ch (last): $last"
    case "$last" in
      t_s,*|"") echo "FAIL: $file: no TILLER_HEARTBEAT_$ch in the log"; fail=1;;
      *"$want"*) ;;
      *) echo "FAIL: $file: TILLER_HEARTBEAT_$ch does not say '$want'"; fail=1;;
    esac
  done
  grep -v '^logger' "$dir/out" | tail -12
done
[ $fail -eq 0 ] && echo "real_vehicle_launch_test: ok"
exit $fail
