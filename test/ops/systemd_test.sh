#!/bin/sh
# tools/systemd/tiller@.service passes `systemd-analyze verify` without a single warning (an
# [Unit] key under [Service], say, is only warned about and then ignored by systemd), keeps the
# settings docs/operations.md promises (start limit under [Unit], no restart loop on exit 2, the
# real-time limits the launch files need), and names a
# launch file that exists for the documented instance. The unit's /opt/tiller is replaced by
# this tree so ExecStart names a real program. Skipped (exit 77) only when systemd-analyze is
# not installed. Args: SOURCE_DIR BUILD_DIR
set -u
src="$1"; build="$2"
unit="$src/tools/systemd/tiller@.service"
fail=0
section_of() {  # section_of KEY: the [Section] the key is in
  awk -v k="$1" '/^\[/ { s = $0 } index($0, k "=") == 1 { print s }' "$unit"
}
[ "$(section_of StartLimitIntervalSec)" = "[Unit]" ] || { echo "FAIL: StartLimitIntervalSec not under [Unit]"; fail=1; }
[ "$(section_of StartLimitBurst)" = "[Unit]" ] || { echo "FAIL: StartLimitBurst not under [Unit]"; fail=1; }
grep -q '^RestartPreventExitStatus=2$' "$unit" || { echo "FAIL: no RestartPreventExitStatus=2"; fail=1; }
# Real time: the unit grants every SCHED_FIFO priority the real-vehicle launch files ask for
# (LimitRTPRIO >= the largest realtime.priority) and unlimited locked memory (docs/operations.md).
[ "$(section_of LimitRTPRIO)" = "[Service]" ] || { echo "FAIL: LimitRTPRIO not under [Service]"; fail=1; }
grep -q '^LimitMEMLOCK=infinity$' "$unit" || { echo "FAIL: no LimitMEMLOCK=infinity"; fail=1; }
rtprio=$(sed -n 's/^LimitRTPRIO=//p' "$unit")
want=$(cat "$src"/config/launch/real_*.yaml | sed -n 's/.*realtime: *{[^}]*priority: *\([0-9]*\).*/\1/p' | sort -n | tail -1)
if [ -z "$want" ]; then
  echo "FAIL: no realtime: priority in config/launch/real_*.yaml"; fail=1
elif [ "${rtprio:-0}" -lt "$want" ]; then
  echo "FAIL: LimitRTPRIO=$rtprio is below the launch files' priority $want"; fail=1
fi
[ -f "$src/config/launch/real_seed001_rov.yaml" ] || { echo "FAIL: the documented instance's launch file is missing"; fail=1; }
if ! command -v systemd-analyze > /dev/null 2>&1; then
  echo "SKIP: systemd-analyze is not installed (apt-get install systemd); the static checks above ran"
  [ $fail -eq 0 ] && exit 77
  exit $fail
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
sed "s|/opt/tiller/build/bin|$build/bin|g; s|/opt/tiller|$src|g" "$unit" > "$tmp/tiller@.service"
out=$(systemd-analyze verify "$tmp/tiller@.service" 2>&1); rc=$?
echo "systemd-analyze verify: exit $rc${out:+, said:}"
[ -n "$out" ] && echo "$out"
[ $rc -eq 0 ] || { echo "FAIL: systemd-analyze verify exited $rc"; fail=1; }
[ -z "$out" ] || { echo "FAIL: systemd-analyze verify printed warnings (above)"; fail=1; }
[ $fail -eq 0 ] && echo "systemd_test: ok"
exit $fail
