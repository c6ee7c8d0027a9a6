#!/usr/bin/env bash
# `triax diagnose` and `triax ensemble` on a tiny DEM case (about 40 grains (the service e2e test's specimen) sheared to 1 %,
# about a second of CPU per run): threaded with concurrency 2 and 1, then under `mpirun -np 2`
# and `-np 3`. The report and the ensemble files must be byte-identical (they hold no timing).
# usage: same_report.sh TRIAX MPIRUN DATA_DIR
set -euo pipefail
triax="$1"; mpirun="$2"; data="$3"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
export OMPI_MCA_rmaps_base_oversubscribe=1
mpi=("$mpirun" --allow-run-as-root --oversubscribe -np)
diag=(diagnose --scheme "$data/tiny_scheme.json" --dataset "$data/tiny_lab.csv" --options "$data/tiny_options.json")
ens=(ensemble --scheme "$data/tiny_scheme.json" --seeds 1-3)

"$triax" "${diag[@]}" --out "$work/report-threads.json" 2>"$work/diag-threads.log"
sed 's/"concurrency": *[0-9]*/"concurrency": 1/' "$data/tiny_options.json" > "$work/options-serial.json"
grep -q '"concurrency": 1' "$work/options-serial.json"
"$triax" diagnose --scheme "$data/tiny_scheme.json" --dataset "$data/tiny_lab.csv" --options "$work/options-serial.json" \
  --out "$work/report-serial.json" 2>"$work/diag-serial.log"
"$triax" "${ens[@]}" --concurrency 2 --out "$work/ens-threads" >/dev/null 2>"$work/ens-threads.log"
for np in 2 3; do
  "${mpi[@]}" "$np" "$triax" "${diag[@]}" --out "$work/report-np$np.json" 2>"$work/diag-np$np.log"
  "${mpi[@]}" "$np" "$triax" "${ens[@]}" --out "$work/ens-np$np" >/dev/null 2>"$work/ens-np$np.log"
done
status=0
cmp "$work/report-threads.json" "$work/report-serial.json" || { echo "diagnose report differs between concurrency 2 and 1"; status=1; }
for np in 2 3; do
  cmp "$work/report-threads.json" "$work/report-np$np.json" || { echo "diagnose report differs at -np $np"; status=1; }
  for f in ensemble.json shear_band.csv creep_band.csv; do
    cmp "$work/ens-threads/$f" "$work/ens-np$np/$f" || { echo "ensemble $f differs at -np $np"; status=1; }
  done
  grep -q "^progress " "$work/diag-np$np.log" || { echo "no progress lines from rank 0 at -np $np"; status=1; }
done
grep -h "wall time" "$work"/*.log
exit $status
