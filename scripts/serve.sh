#!/usr/bin/env bash
# The README's run command: installs what is missing, builds, and starts triaxd on
# 127.0.0.1:8080 with its SQLite store in ./data (override with TRIAX_PORT, TRIAX_DATA_DIR).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
TRIAX_WITH_BROWSER=0 "$here/scripts/install-deps.sh"
"$here/scripts/build.sh"
build="${TRIAX_BUILD_DIR:-$here/build}"
exec "$build/server/triaxd" --host "${TRIAX_HOST:-127.0.0.1}" --port "${TRIAX_PORT:-8080}" \
  --data-dir "${TRIAX_DATA_DIR:-$here/data}" "$@"
