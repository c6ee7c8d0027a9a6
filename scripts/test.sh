#!/usr/bin/env bash
# The README's test command: installs what is missing, builds, runs every test
# (engine, protocol, service over loopback, diagnosis, and the page in headless Chromium).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$here/scripts/install-deps.sh"
"$here/scripts/build.sh"
build="${TRIAX_BUILD_DIR:-$here/build}"
cd "$build"
ctest --output-on-failure -j "${TRIAX_TEST_JOBS:-2}" "$@"
