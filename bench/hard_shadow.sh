#!/usr/bin/env bash
# The error estimate on a hard shadow (docs/notebook/accuracy-measurements.md, "Hard shadows"): a
# room lit by a small lamp with a table top floating under it (bench/shadow_room.py), solved at
# several patch sizes, each result's own estimate of its error (sampling and discretisation) against
# the error that `verify` measures with the independent path tracer (its noise taken out).
# Usage: bash bench/hard_shadow.sh BUILD_DIR OUT_DIR [RANKS]
#   bash bench/hard_shadow.sh build docs/accuracy 2      (about 4 minutes on 2 idle cores)
# Environment: AREAS ("1.0 0.45 0.3 0.08 auto") the --max-area of each run (auto: the default
# mesh), RAYS (4096), PATCHES (1000) and PATHS (65536) for verify.
# Writes OUT_DIR/hard_shadow.csv (a row per run and channel) and OUT_DIR/logs/hard_shadow_*.
set -euo pipefail
cd "$(dirname "$0")/.."
build=$1 out=$2 ranks=${3:-2}
areas=${AREAS:-1.0 0.45 0.3 0.08 auto} rays=${RAYS:-4096}
patches=${PATCHES:-1000} paths=${PATHS:-65536}
mkdir -p "$out/logs"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
run() { mpiexec -n "$ranks" "$build/radiosity" "$@"; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
python3 bench/shadow_room.py "$work"

csv="$out/hard_shadow.csv"
echo "max_area,rays,patches,channel,measured,sampling_estimate,discretisation_estimate,estimate_over_measured,coverage" >"$csv"
for area in $areas; do
  name="area_$area"
  mesh=()
  [ "$area" = auto ] || mesh=(--max-area "$area")
  run solve "$work/shadow.obj" "${mesh[@]}" --rays "$rays" -o "$work/$name.h5" \
    >"$out/logs/hard_shadow_${name}_solve.txt" 2>&1
  run verify "$work/$name.h5" --patches "$patches" --paths "$paths" --tol 1 \
    >"$out/logs/hard_shadow_${name}_verify.txt" 2>&1
  count=$(grep -o -- '-> [0-9]* patches' "$out/logs/hard_shadow_${name}_solve.txt" | grep -o '[0-9]*')
  # The solve's split of its estimate (sampling, discretisation) over all reflecting patches.
  split=$(grep -o 'sampling [0-9.e-]* / [0-9.e-]* / [0-9.e-]*, discretisation [0-9.e-]* / [0-9.e-]* / [0-9.e-]*' \
    "$out/logs/hard_shadow_${name}_solve.txt" | tr -d ',/' | awk '{print $2, $3, $4, $6, $7, $8}')
  awk -v area="$area" -v rays="$rays" -v count="$count" -v parts="$split" '
    /measured, noise taken out/ {for (c = 0; c < 3; ++c) o[c] = $(NF - 2 + c)}
    /estimate \/ measured/ {for (c = 0; c < 3; ++c) r[c] = $(NF - 2 + c)}
    /coverage/ {for (c = 0; c < 3; ++c) v[c] = $(NF - 5 + 2 * c)}
    END {
      split("red green blue", channel, " ")
      split(parts, s, " ")
      for (c = 0; c < 3; ++c)
        print area "," rays "," count "," channel[c + 1] "," o[c] "," s[c + 1] "," s[c + 4] \
              "," r[c] "," v[c]
    }' "$out/logs/hard_shadow_${name}_verify.txt" >>"$csv"
  echo "max-area $area: $count patches"
done
column -s, -t "$csv"
