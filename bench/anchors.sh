#!/usr/bin/env bash
# Throughput anchors: triax's engine_bench against LAMMPS and YADE (Debian packages) on
# dense packings of N spheres (r 1-3 mm, linear spring + Coulomb friction 0.4), one run
# after the other, and one table of particle-steps/s with each packing's coordination.
# Never run by CI (minutes; installs packages). Run it on a quiet machine and quote ratios.
#
# usage: bench/anchors.sh [N=10000] [steps=5000]
#   TRIAX_BUILD_DIR   build tree with bench/engine_bench (default: build)
#   ANCHOR_DIR        work directory: logs, the engine_bench packing cache (default /tmp/triax_anchors)
#   ANCHORS           which runs (default "triax lammps lammps_triax yade")
#
# Rows:
#   triax engine_bench      servo-compressed box (six walls, 100 kPa), 1 and 2 threads
#   LAMMPS periodic         bench/anchors/lammps_dense_periodic.in: its own periodic packing
#                           (solid fraction 0.667), 1 and 2 MPI ranks
#   LAMMPS, triax packing   bench/anchors/lammps_triax_packing.in: engine_bench's packing
#                           (exported as a LAMMPS data file), walls as wall/gran planes, the
#                           same law, skin and time step, 1 and 2 ranks: the same packing
#   YADE                    bench/anchors/yade_dense_box_bench.py: box compacted to 100 kPa, 2 threads
# Rates are wall-clock (particle-steps per second); "per core" divides by threads/ranks;
# "per CPU-s" divides by the CPU time the run got (engine_bench's getrusage, LAMMPS's
# "% CPU use"), the figure that still means something when other jobs share the machine.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
N="${1:-10000}"
STEPS="${2:-5000}"
build="${TRIAX_BUILD_DIR:-$here/build}"
dir="${ANCHOR_DIR:-/tmp/triax_anchors}"
runs="${ANCHORS:-triax lammps lammps_triax yade}"
inputs="$here/bench/anchors"
mkdir -p "$dir"

if [[ -n "${CI:-}" ]]; then
  echo "anchors.sh: a benchmark, not for CI" >&2
  exit 2
fi

# Debian packages: lmp (lammps), mpirun (openmpi-bin), yade.
missing=()
command -v lmp >/dev/null || missing+=(lammps)
command -v mpirun >/dev/null || missing+=(openmpi-bin)
command -v yade >/dev/null || missing+=(yade)
if ((${#missing[@]})); then
  echo "installing ${missing[*]} (apt-get)" >&2
  apt-get install -y "${missing[@]}" >/dev/null 2>&1 || { apt-get update >/dev/null && apt-get install -y "${missing[@]}" >/dev/null; }
fi
[[ -x "$build/bench/engine_bench" ]] || { echo "anchors.sh: $build/bench/engine_bench not built" >&2; exit 2; }

rows=()
# engine, threads/ranks, particle-steps/s (wall), per core, per CPU-second, coordination
row() { rows+=("$(printf '| %-34s | %-13s | %10s | %10s | %11s | %12s |' "$1" "$2" "$3" "$4" "$5" "$6")"); }
per_core() { awk -v r="$1" -v n="$2" 'BEGIN { printf "%.3g", r / n }'; }

# --- triax engine_bench ---------------------------------------------------------------------
pack="$dir/pack_$N.bin"
data="$dir/pack_$N.data"
if [[ " $runs " == *" triax "* || " $runs " == *" lammps_triax "* ]]; then
  echo "triax engine_bench (N=$N; the first run builds and caches the packing: minutes) ..." >&2
  OMP_WAIT_POLICY=passive "$build/bench/engine_bench" "$N" "$STEPS" 3 --no-scaling --packing "$pack" \
    --lammps-data "$data" >"$dir/triax.log" 2>"$dir/triax.err"
  coord=$(sed -n 's/.*coordination \([0-9.]*\),.*/\1/p' "$dir/triax.log")
  dt=$(sed -n 's/.*, dt \([0-9.e+-]*\) s,.*/\1/p' "$dir/triax.log")
  for t in 1 2; do
    rate=$(sed -n "s/^threads=$t: .*-> \([0-9.e+]*\) particle-steps\/s;.*/\1/p" "$dir/triax.log")
    cpu=$(sed -n "s/^threads=$t: .*-> \([0-9.e+]*\) particle-steps per CPU-second/\1/p" "$dir/triax.log")
    [[ " $runs " == *" triax "* ]] && row "triax engine_bench (box, walls)" "$t thread(s)" "$rate" "$(per_core "$rate" "$t")" "$cpu" "$coord"
  done
fi

# --- LAMMPS ----------------------------------------------------------------------------------
# Loop time of the last run (the timed one) -> N * steps / s; coordination = last thermo row's c_cavg.
lammps_rate() { awk -v n="$2" '/^Loop time of/ { t = $4; s = $9 } END { printf "%.3g", n * s / t }' "$1"; }
# Per CPU-second: "X% CPU use with P MPI tasks" (the mean over the tasks) after the timed loop.
lammps_cpu_rate() {
  awk -v n="$2" -v np="$3" '/^Loop time of/ { t = $4; s = $9 } /% CPU use with/ { c = $1 + 0 } END { printf "%.3g", n * s / (t * np * c / 100) }' "$1"
}
lammps_coord() { awk '/^ *Step +Press +c_cavg/ { on = 1; next } on && /^Loop time/ { on = 0 } on && NF == 4 { c = $3 } END { printf "%.2f", c }' "$1"; }
run_lammps() {  # label input log-name extra-vars...
  local label="$1" input="$2" name="$3"
  shift 3
  for np in 1 2; do
    local log="$dir/$name.np$np.log"
    echo "$label, $np rank(s) ..." >&2
    if [[ $np == 1 ]]; then
      (cd "$dir" && OMP_NUM_THREADS=1 lmp -in "$input" -log "$log" -screen none "$@")
    else
      (cd "$dir" && OMP_NUM_THREADS=1 mpirun --allow-run-as-root --oversubscribe -np "$np" lmp -in "$input" -log "$log" -screen none "$@")
    fi
    local rate
    rate=$(lammps_rate "$log" "$N")
    row "$label" "$np rank(s)" "$rate" "$(per_core "$rate" "$np")" "$(lammps_cpu_rate "$log" "$N" "$np")" "$(lammps_coord "$log")"
  done
}
if [[ " $runs " == *" lammps "* ]]; then
  run_lammps "LAMMPS periodic (own packing)" "$inputs/lammps_dense_periodic.in" lammps_periodic -var N "$N"
fi
if [[ " $runs " == *" lammps_triax "* ]]; then
  run_lammps "LAMMPS, triax packing (walls)" "$inputs/lammps_triax_packing.in" lammps_triax -var data "$data" -var dt "$dt" -var steps "$STEPS"
fi

# --- YADE ------------------------------------------------------------------------------------
if [[ " $runs " == *" yade "* ]]; then
  echo "YADE, 2 threads (compaction up to 400 s) ..." >&2
  (cd "$dir" && yade -n -x -j2 "$inputs/yade_dense_box_bench.py" "$N" >"$dir/yade.log" 2>&1) || true
  yrate=$(sed -n 's/.*particle-steps\/s=\([0-9.e+]*\) .*/\1/p' "$dir/yade.log" | tail -1)
  ycoord=$(sed -n 's/.*coord=\([0-9.]*\) .*/\1/p' "$dir/yade.log" | tail -1)
  row "YADE (box, 100 kPa)" "2 threads" "${yrate:-failed}" "$( [[ -n "$yrate" ]] && per_core "$yrate" 2 || echo -)" "-" "${ycoord:--}"
fi

echo
echo "N = $N spheres, $STEPS timed steps (LAMMPS periodic and YADE: 5000, as in their inputs); $(date -u '+%Y-%m-%d %H:%M UTC'), load average $(cut -d' ' -f1-3 /proc/loadavg); logs in $dir"
echo
printf '| %-34s | %-13s | %10s | %10s | %11s | %12s |\n' "engine" "threads/ranks" "p-steps/s" "per core" "per CPU-s" "coordination"
printf '|%s|%s|%s|%s|%s|%s|\n' "------------------------------------" "---------------" "------------" "------------" "-------------" "--------------"
printf '%s\n' "${rows[@]}"
