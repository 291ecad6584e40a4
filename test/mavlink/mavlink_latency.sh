#!/bin/sh
# Starts tiller-mavlink (config/mavlink/usv_sim.yaml, a fresh key) and runs mavlink_latency against
# it, inside a private network namespace: test/mavlink/mavlink_latency.sh SOURCE_DIR BUILD_DIR
# (from the repository root: tools/netns-run test/mavlink/mavlink_latency.sh . build).
set -u
src="$1"; build="$2"
if [ -z "${TILLER_NETNS:-}" ]; then exec env TILLER_NETNS=1 "$src/tools/netns-run" "$0" "$@"; fi
work=$(mktemp -d /tmp/tiller-mavlink-latency-XXXXXX)
"$build/bin/tiller-key" new "$work/k.key" > /dev/null
export TILLER_KEY_FILE="$work/k.key"
secret=$("$build/bin/tiller-mavlink" --config "$src/config/mavlink/usv_sim.yaml" --print-secret)
"$build/bin/tiller-mavlink" --config "$src/config/mavlink/usv_sim.yaml" > "$work/mavlink.log" 2>&1 &
pid=$!
sleep 1
"$build/bench/mavlink_latency" "$secret" "${SAMPLES:-2000}"
status=$?
kill -INT $pid; wait $pid
rm -rf "$work"
exit $status
