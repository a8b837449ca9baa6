#!/usr/bin/env bash
# The discretisation estimate on one rank's threads: the same solve with --threads 1 and
# --threads T (default 2), its estimate's seconds from each log ("discretisation from N rays
# (S s)"), their ratio, and whether the estimate per patch is the same bit for bit (h5diff).
# Usage: bench/discretisation_threads.sh [SCENE] [RAYS] [THREADS] [REPEATS]
#   bench/discretisation_threads.sh 'builtin:rooms?patches=100000' 64 2 3
# RADIOSITY=path/to/radiosity measures another build (default build/radiosity). Runs on one
# rank; the median of REPEATS runs each way.
set -euo pipefail
cd "$(dirname "$0")/.."
scene=${1:-builtin:rooms?patches=100000}
rays=${2:-64}
threads=${3:-2}
repeats=${4:-3}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

seconds() {  # the estimate's seconds of one run on $1 threads, its result in $work/t$1.h5
  "${RADIOSITY:-build/radiosity}" solve "$scene" --rays "$rays" --refine-rounds 0 \
    --threads "$1" -o "$work/t$1.h5" >"$work/log" 2>&1
  sed -n 's/.*discretisation from [0-9]* rays (\([0-9.]*\) s).*/\1/p' "$work/log"
}
median() { sort -g | awk '{v[NR] = $1} END {print v[int((NR + 1) / 2)]}'; }
one=$(for _ in $(seq "$repeats"); do seconds 1; done | median)
many=$(for _ in $(seq "$repeats"); do seconds "$threads"; done | median)
printf 'estimate, median of %s: %s s on 1 thread, %s s on %s threads: %.2fx\n' \
  "$repeats" "$one" "$many" "$threads" "$(awk -v a="$one" -v b="$many" 'BEGIN {print a / b}')"
if h5diff --delta=0 "$work/t1.h5" "$work/t$threads.h5" /patches/radiosity_discretisation \
  >/dev/null; then
  echo "/patches/radiosity_discretisation: the same bit for bit"
else
  echo "/patches/radiosity_discretisation: differs"
  exit 1
fi
