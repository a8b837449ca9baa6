#!/usr/bin/env bash
# Peak memory per nonzero of F, the figure behind run/memory_check.h (kBytesPerNonzero): the
# growth of the maximum resident set (/usr/bin/time -v) between two sizes of a scene, divided
# by the growth of F's nonzeros (from the solve log), so that the fixed cost drops out.
# Usage: bench/memory_per_nonzero.sh [SCENE] [RAYS] [SMALL] [LARGE]
#   bench/memory_per_nonzero.sh builtin:cornell 256 5000 20000
# RADIOSITY=path/to/radiosity measures another build (default build/radiosity). The growth
# includes what grows with the patches too (vectors, the Krylov basis, the mesh), which the
# nonzeros grow with here; docs/notebook/scaling-measurements.md also measures at fixed patches.
set -euo pipefail
cd "$(dirname "$0")/.."
scene=${1:-builtin:cornell}
rays=${2:-256}
small=${3:-5000}
large=${4:-20000}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

measure() {  # prints "nonzeros kilobytes" for --patches $1
  /usr/bin/time -v "${RADIOSITY:-build/radiosity}" solve "$scene" --patches "$1" --rays "$rays" -o "$work/r.h5" \
    >"$work/log" 2>&1
  local nonzeros kilobytes
  nonzeros=$(sed -n 's/.* \([0-9]*\) nonzeros (.*/\1/p' "$work/log")
  kilobytes=$(sed -n 's/.*Maximum resident set size (kbytes): //p' "$work/log")
  echo "$nonzeros $kilobytes"
}
read -r n1 k1 < <(measure "$small")
read -r n2 k2 < <(measure "$large")
printf 'patches %s: %s nonzeros, %s kB peak\npatches %s: %s nonzeros, %s kB peak\n' \
  "$small" "$n1" "$k1" "$large" "$n2" "$k2"
awk -v n1="$n1" -v n2="$n2" -v k1="$k1" -v k2="$k2" \
  'BEGIN {printf "bytes per nonzero at the peak: %.1f\n", (k2 - k1) * 1024 / (n2 - n1)}'
