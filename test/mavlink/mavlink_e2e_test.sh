#!/bin/sh
# tiller-mavlink end to end (test/mavlink/gcs/gcs_test.js: node-mavlink as the ground station)
# against the simulated USV stack (config/launch/sim_usv_mavlink.yaml), inside tools/netns-run
# (UDP 14550/14551 on this namespace's loopback only). A fresh key for the run; the station's
# secret from tiller-mavlink --print-secret. Exit 77 (skipped) without node-mavlink installed
# (tools/setup: npm ci). Args: SOURCE_DIR BUILD_DIR
set -u
src="$1"; build="$2"
gcs="$src/test/mavlink/gcs"
[ -d "$gcs/node_modules/node-mavlink" ] || { echo "node-mavlink not installed (tools/setup); skipped"; exit 77; }
work=$(mktemp -d /tmp/tiller-mavlink-e2e-XXXXXX)
"$build/bin/tiller-key" new "$work/sim.key" > /dev/null
export TILLER_KEY_FILE="$work/sim.key"
secret=$("$build/bin/tiller-mavlink" --config "$src/config/mavlink/usv_sim.yaml" --print-secret)
cd "$src"
"$build/bin/tiller-launch" config/launch/sim_usv_mavlink.yaml --log-file "$work/run.lcmlog" \
  > "$work/launch.log" 2>&1 &
launch=$!
timeout 50 node "$gcs/gcs_test.js" "$secret"
status=$?
kill -INT $launch; wait $launch
if [ $status -ne 0 ]; then tail -30 "$work/launch.log"; fi

rm -rf "$work"
exit $status
