#!/usr/bin/env bash
# Installs what the build, the service and the tests need, and only what is missing:
# Debian packages through apt-get; through npm the page's plotting and 3D packages (web/,
# served by triaxd at /vendor/) and the browser-test driver (tests/web/).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"

pkgs=(build-essential cmake pkg-config libeigen3-dev libcpp-httplib-dev nlohmann-json3-dev
      libsqlite3-dev sqlite3 zlib1g-dev catch2 libomp-dev curl iproute2 clang
      libopenmpi-dev openmpi-bin)
# npm fetches the page's packages (uplot, three) for every install, the service's too.
command -v node >/dev/null 2>&1 || pkgs+=(nodejs)
command -v npm >/dev/null 2>&1 || pkgs+=(npm)
if [[ "${TRIAX_WITH_BROWSER:-1}" == 1 ]]; then pkgs+=(chromium); fi

missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "install-deps: installing ${missing[*]}" >&2
  sudo_cmd=""
  [[ $(id -u) -ne 0 ]] && sudo_cmd="sudo"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# The page's packages: installed again when web/package.json is newer than the install.
if [[ ! -f "$here/web/node_modules/.package-lock.json" || "$here/web/package.json" -nt "$here/web/node_modules/.package-lock.json" ]]; then
  echo "install-deps: npm install in web" >&2
  (cd "$here/web" && npm install --no-audit --no-fund --loglevel=error && touch node_modules/.package-lock.json)
fi

if [[ "${TRIAX_WITH_BROWSER:-1}" == 1 && -f "$here/tests/web/package.json" ]]; then
  if [[ ! -d "$here/tests/web/node_modules/playwright-core" ]]; then
    echo "install-deps: npm install in tests/web" >&2
    (cd "$here/tests/web" && npm install --no-audit --no-fund --loglevel=error)
  fi
fi
