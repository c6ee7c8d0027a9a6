#!/usr/bin/env bash
# Cross-engine check (never run by CI): the same box packing, isotropic compression to
# 100 kPa and drained shear to 10 % axial strain in triax and in YADE, side by side.
#   bench/cross_engine/run.sh [BUILD_DIR=build] [OUT_DIR=/tmp/triax-cross-engine] [N=2000] [ISO_STEPS=60000] [RATE_PER_S=2]
# Installs Debian's yade when it is missing (root or sudo). Both runs are niced; on two
# cores the triax side takes minutes and YADE several times longer.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
build="${1:-build}"
out="${2:-/tmp/triax-cross-engine}"
n="${3:-2000}"
iso="${4:-60000}"
rate="${5:-2}"
if ! command -v yade >/dev/null 2>&1; then
  sudo_cmd=""
  [[ $(id -u) -ne 0 ]] && sudo_cmd="sudo"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq yade
fi
mkdir -p "$out"
nice "$build/bench/cross_engine_box" "$out" "$n" "$iso" "$rate" 2>&1 | tee "$out/triax.log"
XE_DIR="$out" OMP_NUM_THREADS=1 nice yade -n -j1 -x "$here/yade_box.py" 2>&1 | tee "$out/yade.log"
python3 "$here/compare.py" "$out"
