#!/usr/bin/env bash
# Adaptive refinement against the uniform mesh (docs/notebook/accuracy-measurements.md, "Adaptive
# refinement"): each case solved with the first mesh only (--refine-rounds 0), with the default (one
# round where the error is mostly the mesh's), and with --target-error, and measured by `verify`
# (the independent path tracer, its noise taken out). Per run: patches, rounds, the estimated and
# the measured error (largest channel), wall seconds and the peak resident set of a rank.
# Usage: bash bench/adaptive_refinement.sh BUILD_DIR OUT_DIR [RANKS]
#   bash bench/adaptive_refinement.sh build docs/accuracy 2   (about 15 minutes on 2 idle cores)
# Environment: PATCHES (400) and PATHS (16384) for verify.
# Writes OUT_DIR/adaptive_refinement.csv and OUT_DIR/logs/adaptive_*.
set -euo pipefail
cd "$(dirname "$0")/.."
build=$1 out=$2 ranks=${3:-2}
patches=${PATCHES:-400} paths=${PATHS:-16384}
mkdir -p "$out/logs"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
python3 bench/shadow_room.py "$work"

csv="$out/adaptive_refinement.csv"
echo "case,options,patches,rounds,estimated,measured,seconds,peak_rank_mb" >"$csv"
# case NAME SCENE OPTIONS...: one solve and its verify, a row of the CSV.
case_() {
  local name=$1 scene=$2
  shift 2
  local log="$out/logs/adaptive_${name}_solve.txt"
  /usr/bin/time -v mpiexec -n "$ranks" "$build/radiosity" solve "$scene" "$@" \
    -o "$work/$name.h5" >"$log" 2>&1
  mpiexec -n "$ranks" "$build/radiosity" verify "$work/$name.h5" --patches "$patches" \
    --paths "$paths" --tol 1 >"$out/logs/adaptive_${name}_verify.txt" 2>&1
  local count rounds estimated measured seconds peak
  count=$( (grep -o -- '-> [0-9]* patches' "$log" || true) | tail -1 | grep -o '[0-9]*')
  rounds=$(grep -c '^refinement round' "$log" || true)
  estimated=$(grep 'estimated error of B' "$log" | tail -1 |
    sed 's/.*relative to its own B): \([^(]*\) (sampling.*/\1/' | tr -d '/' |
    awk '{m = $1; for (i = 2; i <= NF; ++i) if ($i > m) m = $i; print m}')  # 1 or 3 channels
  measured=$(awk '/measured, noise taken out/ {m = $(NF - 2); if ($(NF - 1) > m) m = $(NF - 1);
    if ($NF > m) m = $NF; print m}' "$out/logs/adaptive_${name}_verify.txt")
  seconds=$(awk -F': ' '/Elapsed \(wall clock\)/ {n = split($2, t, ":"); s = 0;
    for (i = 1; i <= n; ++i) s = s * 60 + t[i]; print s}' "$log")
  peak=$(awk -F': ' '/Maximum resident set size/ {printf "%.0f", $2 / 1024}' "$log")
  echo "$name,\"$*\",$count,$rounds,$estimated,$measured,$seconds,$peak" >>"$csv"
  echo "$name: $count patches, $rounds rounds, estimated $estimated, measured $measured"
}
rooms='builtin:rooms?patches=20000'
case_ rooms_uniform "$rooms" --refine-rounds 0
case_ rooms_default "$rooms"
case_ rooms_target5 "$rooms" --target-error 0.05
case_ shadow_uniform "$work/shadow.obj" --max-area 0.45 --rays 4096 --refine-rounds 0
case_ shadow_rounds2 "$work/shadow.obj" --max-area 0.45 --rays 4096 --refine-rounds 2
case_ shadow_fine "$work/shadow.obj" --max-area 0.08 --rays 4096 --refine-rounds 0
column -s, -t "$csv"
