#!/usr/bin/env bash
# View-factor accuracy per ray and per second of the form-factor estimator (issue 16, item 3;
# docs/notebook/accuracy-measurements.md, "View factors per ray: the city and the cube"): the
# yardstick for work on the error per ray. Every run keeps the scene's own triangles as patches
# (--max-area 1e9), uses the hemisphere estimator (view factors: no emitters involved) and saves F
# (--save-formfactors); bench/view_factor_accuracy.py compares it with a reference.
#  (a) builtin:city (5,016 triangles): reference = the mean of CITY_REFS high-effort runs of
#      CITY_REF_RAYS rays with seeds 101, 102, ... (their spread gives the reference's noise);
#      runs of CITY_RAYS with seed 1: RMS error of the row sums (1 - sky view factor) per patch,
#      plain and area-weighted, and RMS relative error of the building-to-building group factors.
#  (b) the closed unit cube with CUBE_N x CUBE_N squares a face (two triangles each) against the
#      exact square-to-square factors (closed forms, by Stokes' theorem): mean absolute error of
#      the square-pair factors, and the row sums against 1. First as the program runs it (label
#      cubeN-exact: a convex scene's rows are exact, formfactor::chooseRows, with CUBE_EXACT_RAYS
#      = 1024 only deciding that they qualify), then sampled (--exact-rows off) at CUBE_RAYS.
#  (c) builtin:city?element=2.6 (30,066 triangles) likewise (CITY30K_RAYS, CITY30K_REF_RAYS,
#      CITY30K_REFS).
#  (d) the cube of CUBEG_N (13) squares a face as an OBJ with one group per square: its exact
#      rows' /groups (the square-pair factors) against the exact ones, each pair stored once
#      (floats, the default from 4,096 patches, asked for here) and whole (--save-formfactors).
# PARTS chooses which: "city5k cube city30k cubegroups" (all, the default) or any of them.
# Then fits error against rays (least squares in log-log) and extrapolates the rays and time for
# a row-sum RMS error of TARGET (2e-4, View3D's 1.8e-4 on the same kind of city).
# Usage: bash bench/view_factor_accuracy.sh BUILD_DIR OUT_DIR [RANKS]
#   bash bench/view_factor_accuracy.sh build /tmp/vf 2     (10-15 minutes on 2 cores)
#   PARTS=cube CUBE_RAYS="1024 4096" bash bench/view_factor_accuracy.sh build /tmp/vf   (seconds)
# Environment: THREADS (1) per rank; CITY_RAYS ("256 1024 4096 16384 65536"), CITY_REF_RAYS
# (262144), CITY_REFS (2); CUBE_N (20), CUBE_EXACT_RAYS (1024), CUBE_RAYS ("1024 4096 16384
# 65536 262144");
# CITY30K_RAYS ("256 1024 4096"), CITY30K_REF_RAYS (16384), CITY30K_REFS (4; the program
# refuses 32768 rays on 30k patches on a 24 GB node: F's worst case would not fit);
# TARGET (2e-4); GROUP_FLOOR (1e-3).
# Writes OUT_DIR/{city,cube,cube_groups}.csv (one row per run; columns in bench/view_factor_accuracy.py),
# OUT_DIR/fits.txt, OUT_DIR/logs/. The result files go to a temporary directory, removed at exit.
# Needs /usr/bin/python3 with h5py and NumPy.
set -euo pipefail
cd "$(dirname "$0")/.."
build=$1 out=$2 ranks=${3:-2}
threads=${THREADS:-1} target=${TARGET:-2e-4}
python=/usr/bin/python3
helper=bench/view_factor_accuracy.py
mkdir -p "$out/logs"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_rmaps_base_oversubscribe=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

solve() {  # solve SCENE RAYS SEED FILE [OPTIONS...]
  local log scene=$1 rays=$2 seed=$3 file=$4
  shift 4
  log="$out/logs/$(basename "$file" .h5).log"
  echo "solve $scene --rays $rays --seed $seed $*" >&2
  mpiexec -n "$ranks" "$build/radiosity" solve "$scene" --rays "$rays" --seed "$seed" \
    --estimator hemisphere --max-area 1e9 --threads "$threads" --rtol 1e-4 \
    --save-formfactors -o "$file" "$@" >"$log" 2>&1
}

city() {  # city LABEL SCENE "RAYS..." REF_RAYS REFS CSV
  local label=$1 scene=$2 rays=$3 ref_rays=$4 refs=$5 table=$6 k list="" r
  for ((k = 1; k <= refs; ++k)); do
    solve "$scene" "$ref_rays" $((100 + k)) "$work/${label}_ref$k.h5"
    list+="${list:+,}$work/${label}_ref$k.h5"
  done
  for r in $rays; do
    solve "$scene" "$r" 1 "$work/${label}_$r.h5"
    "$python" "$helper" city "$table" "$label" "$list" "$work/${label}_$r.h5"
    rm -f "$work/${label}_$r.h5"
  done
  rm -f "$work/${label}"_ref*.h5
}

rm -f "$out/city.csv" "$out/cube.csv" "$out/cube_groups.csv" "$out/fits.txt"
"$python" "$helper" cube-check >"$out/logs/cube_check.log"

parts=" ${PARTS:-city5k cube city30k cubegroups} "
n=${CUBE_N:-20}

# (a) the city, ~5,000 surfaces
if [[ $parts == *" city5k "* ]]; then
  city city5k builtin:city "${CITY_RAYS:-256 1024 4096 16384 65536}" \
    "${CITY_REF_RAYS:-262144}" "${CITY_REFS:-2}" "$out/city.csv"
fi

# (b) the cube of N x N squares a face
if [[ $parts == *" cube "* ]]; then
  "$python" "$helper" cube-scene "$n" "$work/cube$n.h5"
  # The default: a convex enclosure's rows are exact (closed forms, no rays; the rays only
  # decide whether they qualify, N <= 8 x rays), then rays for the rows (--exact-rows off).
  solve "$work/cube$n.h5" "${CUBE_EXACT_RAYS:-1024}" 1 "$work/cube${n}_exact.h5"
  "$python" "$helper" cube "$out/cube.csv" "cube$n-exact" "$n" "$work/cube${n}_exact.h5"
  rm -f "$work/cube${n}_exact.h5"
  for r in ${CUBE_RAYS:-1024 4096 16384 65536 262144}; do
    solve "$work/cube$n.h5" "$r" 1 "$work/cube${n}_$r.h5" --exact-rows off
    "$python" "$helper" cube "$out/cube.csv" "cube$n" "$n" "$work/cube${n}_$r.h5"
    rm -f "$work/cube${n}_$r.h5"
  done
fi

# (c) the city, ~30,000 surfaces
if [[ $parts == *" city30k "* ]]; then
  city city30k 'builtin:city?element=2.6' "${CITY30K_RAYS:-256 1024 4096}" \
    "${CITY30K_REF_RAYS:-16384}" "${CITY30K_REFS:-4}" "$out/city.csv"
fi

# (d) the cube's square-pair factors through /groups: pairs once against whole rows
if [[ $parts == *" cubegroups "* ]]; then
  ng=${CUBEG_N:-13}
  "$python" "$helper" cube-groups-scene "$ng" "$work/cubeg.obj"
  for mode in pairs whole; do
    extra=()
    [[ $mode == whole ]] && extra=(--save-formfactors)
    mpiexec -n "$ranks" "$build/radiosity" solve "$work/cubeg.obj" --max-area 1e9 --rays 1024 \
      --refine-rounds 0 --formfactor-precision single "${extra[@]}" -o "$work/cubeg_$mode.h5" \
      >"$out/logs/cubeg_$mode.log" 2>&1
    "$python" "$helper" cube-groups "$out/cube_groups.csv" "cube$ng-$mode" "$ng" "$work/cubeg_$mode.h5"
    rm -f "$work/cubeg_$mode.h5"
  done
fi

{
  for label in city5k city30k; do
    grep -qs "^$label," "$out/city.csv" || continue
    for column in rowsum_rms rowsum_rms_corr; do
      "$python" "$helper" fit "$out/city.csv" "$label" "$column" "$target"
    done
    "$python" "$helper" fit "$out/city.csv" "$label" group_rms_rel_corr 0.0037
  done
  if grep -qs "^cube$n," "$out/cube.csv"; then
    "$python" "$helper" fit "$out/cube.csv" "cube$n" pair_mean_abs 7.8e-6
  fi
} | tee "$out/fits.txt"
