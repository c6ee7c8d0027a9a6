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
# The parsers' libFuzzer targets (tests/fuzz, 30 s each) when clang is present: a second
# build tree compiled with clang, ASan and UBSan.
if command -v clang++ >/dev/null 2>&1 && [[ "${TRIAX_WITH_FUZZ:-1}" == 1 ]]; then
  fuzz_build="${TRIAX_FUZZ_BUILD_DIR:-$here/build-fuzz}"
  CC=clang CXX=clang++ cmake -S "$here" -B "$fuzz_build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTRIAX_FUZZ=ON \
    -DTRIAX_BUILD_TESTS=OFF -DTRIAX_BUILD_BENCH=OFF >/dev/null
  cmake --build "$fuzz_build" -j "$(nproc)" --target fuzz_scheme_json fuzz_lab_csv fuzz_lab_gds fuzz_lab_ags \
    fuzz_lab_json fuzz_diagnose_options
  ctest --test-dir "$fuzz_build" --output-on-failure -j "${TRIAX_TEST_JOBS:-2}"
fi
