#!/usr/bin/env bash
# The error of the form-factor estimator on builtin:city from the spread over seeds, and what
# two alternatives would buy on the same rays (bench/seed_spread.py; docs/notebook/history.md,
# "Less error per ray in occluded scenes"): reciprocity as information, and exact values for
# the pairs proven unoccluded within NEAR metres.
# Usage: bash bench/seed_spread.sh BUILD_DIR OUT_DIR [RANKS]   (a solve of the city per seed, 8 by default: minutes)
# Environment: SCENE (builtin:city), RAYS (4096), SEEDS (8), NEAR ("12 30").
set -euo pipefail
cd "$(dirname "$0")/.."
build=$1 out=$2 ranks=${3:-2}
scene=${SCENE:-builtin:city} rays=${RAYS:-4096} seeds=${SEEDS:-8}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_rmaps_base_oversubscribe=1
mkdir -p "$out"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
files=()
for ((s = 1; s <= seeds; ++s)); do
  mpiexec -n "$ranks" "$build/radiosity" solve "$scene" --rays "$rays" --seed "$s" \
    --estimator hemisphere --max-area 1e9 --rtol 1e-4 --save-formfactors -q \
    -o "$work/s$s.h5" >"$out/s$s.log" 2>&1
  files+=("$work/s$s.h5")
done
{
  echo "$scene, $rays rays a patch, seeds 1-$seeds"
  PYTHONPATH=bench /usr/bin/python3 bench/seed_spread.py spread "${files[@]}"
  for r in ${NEAR:-12 30}; do
    PYTHONPATH=bench /usr/bin/python3 bench/seed_spread.py near-field "$r" "${files[@]}"
  done
} | tee "$out/spread.txt"
