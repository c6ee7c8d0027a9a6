#!/bin/sh
# Outside suite: the YADE runs of bench/outside/cases.json, one after another, niced
# (NICE, default 19)
# (bench/outside/README.md). Writes bench/outside/raw/ and then the datasets (make_cases.py).
#   bench/outside/generate.sh [run names...]   (default: all, in the order below)
# The creep runs load the consolidated dense 100 kPa state, so they wait for dense_100.
set -eu
cd "$(dirname "$0")"
RAW=$PWD/raw
STATE=$RAW/state
mkdir -p "$RAW" "$STATE"
one() {  # name sigma3 json-extra
    name=$1; s3=$2; extra=$3
    # Every consolidated state is kept: a shear run again (a change of its recipe) starts
    # from it; the creep runs start from dense 100 kPa's.
    save=$STATE/${name}_${s3}kPa.yade.gz
    case $name in creep_*) save="" ;; esac
    [ -f "$save" ] && extra="$extra,\"state\":\"$save\"" && save=""
    echo "$(date -u +%T) start $name $s3" >&2
    rc=0
    SAVE_STATE=$save OUT_DIR=$RAW OUT_CFG="{\"case\":\"$name\",\"sigma3_kPa\":$s3$extra}" \
        nice -n "${NICE:-19}" yade -n -x yade_triax.py > "$RAW/${name}_${s3}kPa.log" 2>&1 || rc=$?
    echo "$(date -u +%T) done $name $s3 rc=$rc" >&2   # a failed run does not stop the list
}
run() {
    case $1 in
        dense) one dense "$2" "" ;;
        loose) one loose "$2" ',"mu_compact":0.5' ;;
        roll_weak) one roll_weak "$2" ',"eta_roll":0.05' ;;
        roll_strong) one roll_strong "$2" ',"eta_roll":0.2' ;;
        creep_slow|creep_fast)
            c=0.01; [ "$1" = creep_fast ] && c=0.02
            qp=$(python3 -c "import json;print(json.load(open('$RAW/dense_100kPa_shear.json'))['q_peak_kPa'])")
            one "$1" 100 ",\"mode\":\"creep\",\"creep_c\":$c,\"q_peak_kPa\":$qp,\"state\":\"$STATE/dense_100kPa.yade.gz\"" ;;
    esac
}
# Runs its list one after another; the README runs two lists side by side (two cores).
for j in ${*:-dense:100 dense:50 dense:200 creep_fast:100 roll_strong:50 roll_strong:100 roll_strong:200 loose:50 loose:100 loose:200 creep_slow:100 roll_weak:50 roll_weak:100 roll_weak:200}; do
    case $j in creep_*) while [ ! -f "$RAW/dense_100kPa_shear.json" ]; do sleep 10; done ;; esac
    run "${j%%:*}" "${j#*:}"
done
python3 make_cases.py
