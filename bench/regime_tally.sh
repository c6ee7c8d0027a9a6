#!/usr/bin/env bash
# The paper's four creep regimes over groups and seeds: runs the full-size paper-group
# creep test (bench/creep_explore, one thread per run, JOBS runs at a time) for every
# group x seed and tallies, per run and overall, whether
#   S = 0.1  keeps an elastic share >= 0.9 and converges,
#   S = 0.4, S = 0.6  converge and do not accelerate,
#   S = 0.8  accelerates (tertiary, incl. creep rupture) and does not converge
# (the flags of engine/protocol/creep_regime.hpp; docs/creep.md "Regime flags").
# Never run by CI: one run takes 5-17 min on one core.
#
# Usage: bench/regime_tally.sh "A B C D E" "1 2 3" [key=value ...]
#   extra key=value pairs go to creep_explore (bench/reduced_creep_args.hpp), e.g. bmu=0.6
# Env: BUILD (default ./build), JOBS (default 2), OUT (default a new temp dir; the logs stay
# there, and finished runs found there are reused)
set -euo pipefail
groups="${1:?groups, e.g. \"A B C D E\"}"
seeds="${2:?seeds, e.g. \"1 2 3\"}"
shift 2
extra=("$@")
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${BUILD:-$here/build}"
jobs="${JOBS:-2}"
out="${OUT:-$(mktemp -d /tmp/regime_tally.XXXXXX)}"
mkdir -p "$out"
exe="$build/bench/creep_explore"
[[ -x "$exe" ]] || { echo "regime_tally: $exe not built (./scripts/build.sh)" >&2; exit 2; }

runs=() todo=()
for g in $groups; do for s in $seeds; do
  runs+=("$g $s")
  # A finished run already in OUT is reused (a tally can be resumed or extended).
  grep -q '^S=0.80' "$out/$g$s.out" 2>/dev/null || todo+=("$g $s")
done; done
((${#todo[@]} == 0)) || printf '%s\n' "${todo[@]}" | xargs -P "$jobs" -L 1 bash -c '
  g=$0 s=$1
  OMP_NUM_THREADS=1 OMP_WAIT_POLICY=passive "'"$exe"'" group=$g seed=$s '"${extra[*]:-}"' verbose=1 \
    > "'"$out"'/$g$s.out" 2> "'"$out"'/$g$s.err" || echo "regime_tally: run $g seed $s failed (see '"$out"'/$g$s.err)" >&2'

echo "| group | seed | q_f (kPa) | S=0.1 elastic share | S=0.4 | S=0.6 | S=0.8 | four regimes | wall (s) |"
echo "|---|---|---|---|---|---|---|---|---|"
total=0 four=0 tert=0 low=0
for r in "${runs[@]}"; do
  set -- $r
  f="$out/$1$2.out"
  [[ -s "$f" ]] || { echo "| $1 | $2 | (no result) |"; continue; }
  awk -v g="$1" -v s="$2" '
    /^q_f/ { qf = $2; wall = $(NF-1) }
    /^S=/ {
      lvl = substr($1, 3) + 0
      for (i = 1; i <= NF; ++i) {
        if ($i == "elastic") el[lvl] = $(i + 1)
        if ($i == "accel") ac[lvl] = $(i + 1)
        if ($i == "conv") cv[lvl] = $(i + 1)
        if ($i == "rupt") ru[lvl] = $(i + 1)
      }
    }
    function flag(l) { return ac[l] == 1 ? "accelerating" : (cv[l] == 1 ? "converged" : "neither") }
    END {
      s01 = (el[0.1] >= 0.9 && cv[0.1] == 1 && ac[0.1] == 0)
      mid = (cv[0.4] == 1 && ac[0.4] == 0 && cv[0.6] == 1 && ac[0.6] == 0)
      s08 = (ac[0.8] == 1 && cv[0.8] == 0)
      v08 = flag(0.8); if (ru[0.8] + 0 > 0) v08 = sprintf("ruptured at %.1f h", ru[0.8])
      printf "| %s | %s | %s | %s | %s | %s | %s | %s | %s |\n", g, s, qf, el[0.1], flag(0.4), flag(0.6), v08,
             (s01 && mid && s08) ? "yes" : "no", wall
      printf "TALLY %d %d %d\n", (s01 && mid), s08, (s01 && mid && s08) > "/dev/stderr"
    }' "$f" 2> "$out/$1$2.tally"
  read -r _ lo te fo < "$out/$1$2.tally"
  total=$((total + 1)); low=$((low + lo)); tert=$((tert + te)); four=$((four + fo))
done
echo
echo "runs: $total; S = 0.1-0.6 regimes kept: $low; S = 0.8 tertiary: $tert; all four regimes: $four (logs: $out)"
