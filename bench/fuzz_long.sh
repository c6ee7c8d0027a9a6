#!/usr/bin/env bash
# Long fuzzing runs: every libFuzzer target (tests/fuzz) for RUNS executions (default 1e6)
# on its seed corpus, built with clang, ASan and UBSan into build-fuzz/. Prints per target
# the executions, crashes and sanitizer reports. Never run by CI.
#   bench/fuzz_long.sh [RUNS]
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
runs="${1:-1000000}"
build="${TRIAX_FUZZ_BUILD_DIR:-$here/build-fuzz}"
CC=clang CXX=clang++ cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTRIAX_FUZZ=ON \
  -DTRIAX_BUILD_TESTS=OFF -DTRIAX_BUILD_BENCH=OFF >/dev/null
targets=(scheme_json lab_csv lab_gds lab_ags lab_json diagnose_options)
cmake --build "$build" -j "$(nproc)" --target "${targets[@]/#/fuzz_}" >/dev/null
printf '%-18s %12s %8s %10s %8s\n' target executions crashes sanitizer seconds
for t in "${targets[@]}"; do
  work="$build/long/$t"
  mkdir -p "$work/corpus" "$work/artifacts"
  cp -n "$here/tests/fuzz/corpus/$t/"* "$work/corpus/" 2>/dev/null || true
  start=$(date +%s)
  set +e
  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 "$build/tests/fuzz/fuzz_$t" -runs="$runs" -timeout=10 \
    -rss_limit_mb=2048 -max_len=65536 -print_final_stats=1 -artifact_prefix="$work/artifacts/" "$work/corpus" \
    >"$work/log.txt" 2>&1
  set -e
  secs=$(( $(date +%s) - start ))
  execs=$(grep -m1 'stat::number_of_executed_units' "$work/log.txt" | awk '{print $2}')
  crashes=$(find "$work/artifacts" -type f | wc -l)
  reports=$(grep -c -E 'ERROR: AddressSanitizer|runtime error:|ERROR: libFuzzer' "$work/log.txt" || true)
  printf '%-18s %12s %8s %10s %8s\n' "$t" "${execs:-?}" "$crashes" "$reports" "$secs"
done
