#!/bin/sh
# CTest's cockpit_browser_test: test/cockpit/browser_test.js in Debian's chromium (playwright-core
# from test/cockpit/browser/, installed by tools/setup with npm ci). Runs under tools/netns-run.
# Skipped (77) when chromium or the npm package is missing. Args: SOURCE_DIR BUILD_DIR
set -u
src="$1"; build="$2"
[ -x /usr/bin/chromium ] || { echo "skipped: no /usr/bin/chromium (tools/setup installs it)"; exit 77; }
[ -d "$src/test/cockpit/browser/node_modules/playwright-core" ] || {
  echo "skipped: no playwright-core in test/cockpit/browser (tools/setup: npm ci)"; exit 77; }
command -v node > /dev/null || { echo "skipped: no node"; exit 77; }
exec node "$src/test/cockpit/browser_test.js" "$src" "$build" "$build/test-output/cockpit"
