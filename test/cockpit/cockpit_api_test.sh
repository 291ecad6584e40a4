#!/bin/sh
# The documented example client (docs/examples/cockpit_client.py) against the simulated USV stack
# with the cockpit (config/launch/sim_usv_cockpit.yaml), inside tools/netns-run: it reads hello
# and state frames with every process healthy, a command with the token is accepted, one with a
# wrong token is refused, and the cockpit's heartbeat counts it. Args: SOURCE_DIR BUILD_DIR
set -u
src="$1"; build="$2"
work=$(mktemp -d /tmp/tiller-cockpit-api-XXXXXX)
cd "$src"
"$build/bin/tiller-launch" config/launch/sim_usv_cockpit.yaml \
  --log-file "$work/run.lcmlog" > "$work/launch.log" 2>&1 &
launch=$!
fail=0
bad() { echo "FAIL: $*"; fail=1; }
# Wait for the page's server (up to 20 s).
i=0
until python3 -c "import socket; socket.create_connection(('127.0.0.1', 8088), 1)" 2>/dev/null; do
  i=$((i + 1)); [ $i -lt 100 ] || { bad "the cockpit did not listen within 20 s"; break; }
  sleep 0.2
done
sleep 2   # a heartbeat from every process
python3 docs/examples/cockpit_client.py --frames 3 > "$work/read.txt" 2>&1 || bad "the client failed to read"
cat "$work/read.txt"
grep -q "^hello: processes sim, esc, mixer" "$work/read.txt" || bad "no hello"
grep -q "^state: north" "$work/read.txt" || bad "no state frame with odometry"
grep "^state" "$work/read.txt" | tail -1 | grep -q "health sim=OK esc=OK mixer=OK" || bad "a process is not OK"
python3 docs/examples/cockpit_client.py --frames 1 --command '{"type": "mission", "command": "pause"}' \
  > "$work/ok.txt" 2>&1 || bad "a command with the token was refused"
grep '"ok": true' "$work/ok.txt" || bad "no accepted reply"
printf 'not-the-token-0123456789\n' > "$work/wrong.token"
if python3 docs/examples/cockpit_client.py --frames 1 --token-file "$work/wrong.token" \
  --command '{"type": "arm", "arm": true, "confirm": true}' > "$work/refused.txt" 2>&1; then
  bad "a command with a wrong token was accepted"
fi
grep '"ok": false' "$work/refused.txt" || bad "no refusal"
grep -q "wrong token" "$work/refused.txt" || bad "the refusal does not say why"
sleep 1.2  # the cockpit's next heartbeat
kill -INT $launch; wait $launch
# The refusal is in the cockpit's heartbeat (rejected.command.token = 1) in the log.
"$build/bin/tiller-log" summary "$work/run.lcmlog" > "$work/summary.txt" 2>&1
grep -q "TILLER_HEARTBEAT_COCKPIT" "$work/summary.txt" || bad "no cockpit heartbeat in the log"
grep -q "rejected.command.token" "$work/summary.txt" && grep "rejected.command.token" "$work/summary.txt"
[ $fail -eq 0 ] && echo "cockpit_api_test: ok" || tail -20 "$work/launch.log"
rm -rf "$work"
exit $fail
