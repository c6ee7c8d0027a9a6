#!/usr/bin/env bash
# A/B of two builds of bench/forward_run_cost (the diagnosis's forward run): runs OLD and NEW
# alternately REPS times with the same key=value arguments, one OpenMP thread per run, and
# prints per run the CPU seconds (user + system, /usr/bin/time) per particle-step, then the
# median of each and their ratio (old / new: > 1 means NEW is faster). The seeds of one call
# run side by side, so the CPU time, not the wall, is compared.
#
# Usage: bench/forward_ab.sh OLD_BINARY NEW_BINARY REPS key=value...
#   bench/forward_ab.sh /tmp/frc_old build/bench/forward_run_cost 3 seeds=1,2,3 boundary=grain_pressure
set -euo pipefail
old="${1:?old forward_run_cost}"; new="${2:?new forward_run_cost}"; reps="${3:?repetitions}"; shift 3
declare -A cost
for r in $(seq "$reps"); do
  for side in old new; do
    bin=$old; [[ $side == new ]] && bin=$new
    out=$(OMP_NUM_THREADS=1 /usr/bin/time -f "cpu %U %S" "$bin" "$@" 2>&1)
    steps=$(awk '/^seed/{for(i=1;i<=NF;i++) if($i=="particle-steps") s+=$(i-1)} END{print s}' <<<"$out")
    cpu=$(awk '/^cpu/{print $2+$3}' <<<"$out")
    per=$(awk -v c="$cpu" -v s="$steps" 'BEGIN{printf "%.4g", c/s}')
    echo "$side run $r: $cpu CPU s, $steps particle-steps, $per CPU s per particle-step"
    cost[$side]+="$per "
  done
done
median() { tr ' ' '\n' | grep . | sort -g | awk '{a[NR]=$1} END{print (NR%2)?a[(NR+1)/2]:(a[NR/2]+a[NR/2+1])/2}'; }
mo=$(median <<<"${cost[old]}"); mn=$(median <<<"${cost[new]}")
awk -v o="$mo" -v n="$mn" 'BEGIN{printf "median CPU s per particle-step: old %.4g, new %.4g, old/new %.3f\n", o, n, o/n}'
