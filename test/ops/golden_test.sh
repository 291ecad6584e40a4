#!/bin/sh
# Replay regression on the golden logs (test/data/golden): today's code must reproduce every
# process's recorded outputs bit for bit; and a changed gain (the velocity PID's surge k_error,
# 150 -> 160 N per m/s) must be caught, naming the channel, the field and its old and new value.
# If a change of behaviour is intended: tools/rerecord-golden. Args: SOURCE_DIR BUILD_DIR
set -u
src="$1"; bin="$2/bin"
cd "$src"
fail=0
log=test/data/golden/usv_short.lcmlog.gz
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

out=$("$bin/tiller-replay" "$log" 2>&1); rc=$?
echo "$out"
if [ $rc -ne 0 ]; then
  echo "FAIL: today's code does not reproduce $log (if the change is intended: tools/rerecord-golden)"; fail=1
fi
# A lockstep log: every process is in the verdict (none informational), named on the line.
echo "$out" | grep -Eq "^tiller-replay: PASS \(6 processes checked: [a-z-]+(, [a-z-]+){5}; tolerance 0[;,]" ||
  { echo "FAIL: expected all 6 processes checked at tolerance 0"; fail=1; }
echo "$out" | grep -q "^tiller-replay: .*informational" && { echo "FAIL: a lockstep replay left a process out of the verdict"; fail=1; }

# A changed gain is caught.
sed 's/surge: {k_drag: 77.5, k_drag_quad: 0, k_error: 150,/surge: {k_drag: 77.5, k_drag_quad: 0, k_error: 160,/' \
  config/control/otter.yaml > "$tmp/otter_changed.yaml"
cmp -s config/control/otter.yaml "$tmp/otter_changed.yaml" && { echo "FAIL: could not change the gain (config changed?)"; fail=1; }
out=$("$bin/tiller-replay" "$log" --process velocity-pid --config "$tmp/otter_changed.yaml" 2>&1); rc=$?
echo "$out"
[ $rc -eq 1 ] || { echo "FAIL: a changed gain gave exit $rc, expected 1"; fail=1; }
echo "$out" | grep -q "TILLER_WRENCH_VELOCITY *DIFFERENT" || { echo "FAIL: the wrench difference is not reported"; fail=1; }
echo "$out" | grep -Eq "first difference: message [0-9]+ at t=[0-9.]+ s, tau\[0\]: old -?[0-9.e-]+, new -?[0-9.e-]+" ||
  { echo "FAIL: the first difference (time, field, old, new) is not reported"; fail=1; }
# The same change within a generous tolerance passes (the tolerance option works).
"$bin/tiller-replay" "$log" --process velocity-pid --config "$tmp/otter_changed.yaml" --tolerance 1e6 > /dev/null ||
  { echo "FAIL: tolerance 1e6 should accept the changed gain"; fail=1; }
[ $fail -eq 0 ] && echo "golden_test: ok"
exit $fail
