#!/usr/bin/env bash
# A/B throughput of two engine_bench binaries on the same stored packing, run alternately
# (the machine is shared: only alternated runs compare). Never run by CI.
# usage: bench/engine_ab.sh OLD_BINARY NEW_BINARY [runs=5] [threads=1] [steps=2000] [packing=/tmp/triax_pack10k.bin]
# Prints each run (binary, wall particle-steps/s, particle-steps per CPU-second, load
# average) and the medians and new/old ratios. The packing file is built by the first
# run when it does not exist (engine_bench --packing: minutes).
set -euo pipefail
old=$1 new=$2 runs=${3:-5} threads=${4:-1} steps=${5:-2000} pack=${6:-/tmp/triax_pack10k.bin}
log=$(mktemp)
for ((k = 0; k < runs; ++k)); do
  for b in old new; do
    bin=${!b}
    line=$(OMP_WAIT_POLICY=passive "$bin" 10000 "$steps" 1 --packing "$pack" --threads "$threads" --no-scaling 2>/dev/null | grep "^threads=")
    w=$(sed -n 's/.*-> \([0-9.e+]*\) particle-steps\/s;.*/\1/p' <<<"$line")
    c=$(sed -n 's/.*-> \([0-9.e+]*\) particle-steps per CPU-second/\1/p' <<<"$line")
    echo "$b $w $c $(cut -d' ' -f1 /proc/loadavg)" | tee -a "$log"
  done
done
med() { sort -g | awk '{ a[NR] = $1 } END { print a[int((NR + 1) / 2)] }'; }
ow=$(awk '$1 == "old" { print $2 }' "$log" | med); nw=$(awk '$1 == "new" { print $2 }' "$log" | med)
oc=$(awk '$1 == "old" { print $3 }' "$log" | med); nc=$(awk '$1 == "new" { print $3 }' "$log" | med)
awk -v ow="$ow" -v nw="$nw" -v oc="$oc" -v nc="$nc" 'BEGIN {
  printf "medians: old wall %s cpu %s | new wall %s cpu %s | new/old: wall %.3f, cpu %.3f\n", ow, oc, nw, nc, nw / ow, nc / oc }'
rm -f "$log"
