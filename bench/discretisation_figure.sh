#!/usr/bin/env bash
# The discretisation figure against the measured error where it is the whole error
# (docs/notebook/accuracy-measurements.md, "The discretisation figure's noise"): the closed cube of
# N × N squares a face lit by one square (bench/view_factor_accuracy.py cube-scene), whose exact
# rows have no sampling error, solved as the first mesh (--refine-rounds 0) and by default (its
# default round), each result against `verify` (the independent path tracer, its noise taken out).
# Usage: bash bench/discretisation_figure.sh BUILD_DIR OUT_DIR [RANKS]
#   bash bench/discretisation_figure.sh build /tmp/df 2     (about 9 minutes on 2 idle cores)
# Environment: CUBE_N (20), PATCHES (200), PATHS (4194304: the reference's noise ~0.009, below
# the error measured; at 262,144 it is the whole of it), SEED (2) for verify.
# Writes OUT_DIR/discretisation_figure.csv (a row per run) and OUT_DIR/logs/discretisation_*.
# Needs /usr/bin/python3 with h5py and NumPy (Debian's python3-h5py, python3-numpy).
set -euo pipefail
cd "$(dirname "$0")/.."
build=$1 out=$2 ranks=${3:-2}
n=${CUBE_N:-20} patches=${PATCHES:-200} paths=${PATHS:-4194304} seed=${SEED:-2}
mkdir -p "$out/logs"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
run() { mpiexec -n "$ranks" "$build/radiosity" "$@"; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
/usr/bin/python3 bench/view_factor_accuracy.py cube-scene "$n" "$work/cube.h5"

csv="$out/discretisation_figure.csv"
echo "run,patches,figure,estimate_on_sample,measured,measured_low,measured_high,reference_noise" >"$csv"
for name in first default; do
  rounds=()
  [ "$name" = first ] && rounds=(--refine-rounds 0)
  log="$out/logs/discretisation_${name}"
  run solve "$work/cube.h5" "${rounds[@]}" -o "$work/$name.h5" >"${log}_solve.txt" 2>&1
  run verify "$work/$name.h5" --patches "$patches" --paths "$paths" --seed "$seed" --tol 1 \
    >"${log}_verify.txt" 2>&1
  # The figure the run ended with: the last "estimated error, X" of its solves.
  figure=$(grep -o 'estimated error, [0-9.e-]*)' "${log}_solve.txt" | tail -1 | tr -d ')' |
    awk '{print $3}')
  count=$(grep -o '^verify [^:]*: [0-9]* patches' "${log}_verify.txt" | awk '{print $3}')
  awk -v name="$name" -v count="$count" -v figure="$figure" '
    /measured, noise taken out/ {measured = $(NF - 2)}
    /^ *5 % quantile/ {low = $(NF - 2)}
    /95 % quantile/ {high = $(NF - 2)}
    /reference noise/ {noise = $(NF - 2)}
    /file.s own estimate/ {estimate = $(NF - 2)}
    END {print name "," count "," figure "," estimate "," measured "," low "," high "," noise}
  ' "${log}_verify.txt" >>"$csv"
done
cat "$csv"
