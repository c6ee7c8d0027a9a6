#!/usr/bin/env bash
# Browser end-to-end test: start triaxd on a free loopback port with a throw-away data
# directory, wait until /health answers, drive the page in headless Debian Chromium
# (browser_test.mjs), and always stop the server. Installs nothing: playwright-core comes
# from scripts/install-deps.sh (npm install in this folder).
# Usage: tests/web/run.sh <path-to-triaxd>
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
triaxd="${1:?usage: run.sh <path-to-triaxd>}"
[[ -x "$triaxd" ]] || { echo "run.sh: triaxd not executable: $triaxd" >&2; exit 2; }
[[ -d "$here/node_modules/playwright-core" ]] || {
  echo "run.sh: playwright-core missing in $here/node_modules (run scripts/install-deps.sh)" >&2; exit 2; }
[[ -d "$here/../../web/node_modules/uplot" && -d "$here/../../web/node_modules/three" ]] || {
  echo "run.sh: the page's packages are missing in web/node_modules (run scripts/install-deps.sh)" >&2; exit 2; }
[[ -x /usr/bin/chromium ]] || { echo "run.sh: /usr/bin/chromium missing (Debian package chromium)" >&2; exit 2; }

work="$(mktemp -d -t triax-web-XXXXXX)"
server_pid=""
cleanup() {
  if [[ -n "$server_pid" ]] && kill -0 "$server_pid" 2>/dev/null; then
    kill "$server_pid" 2>/dev/null || true
    for _ in $(seq 50); do kill -0 "$server_pid" 2>/dev/null || break; sleep 0.1; done
    kill -9 "$server_pid" 2>/dev/null || true
  fi
  rm -rf "$work"
}
trap cleanup EXIT INT TERM

# Ask the kernel for a free port (bind to 0), then hand it to triaxd. A race with another
# process is possible but unlikely; a failed start is reported below, not retried blindly.
port="$(node -e 'const s=require("net").createServer();s.listen(0,"127.0.0.1",()=>{console.log(s.address().port);s.close();})')"
base="http://127.0.0.1:$port"

"$triaxd" --host 127.0.0.1 --port "$port" --data-dir "$work/data" >"$work/triaxd.log" 2>&1 &
server_pid=$!

for i in $(seq 100); do
  if ! kill -0 "$server_pid" 2>/dev/null; then
    echo "run.sh: triaxd exited during start-up; its log:" >&2; cat "$work/triaxd.log" >&2; exit 1
  fi
  if node -e "fetch('$base/health').then(r=>process.exit(r.ok?0:1)).catch(()=>process.exit(1))"; then break; fi
  if [[ $i == 100 ]]; then echo "run.sh: triaxd did not answer $base/health within 20 s" >&2; cat "$work/triaxd.log" >&2; exit 1; fi
  sleep 0.2
done

status=0
TRIAX_BASE_URL="$base" TRIAX_WEB_TMP="$work" node "$here/browser_test.mjs" || status=$?
if [[ $status != 0 ]]; then
  echo "run.sh: browser test failed (exit $status); last lines of the triaxd log:" >&2
  tail -n 40 "$work/triaxd.log" >&2 || true
fi
exit $status
