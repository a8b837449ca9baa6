#!/usr/bin/env bash
# Wall time of each stage of `radiosity solve` on 1 and 2 ranks: median of REPEAT runs.
# Usage: bench/stage_times.sh [SCENE] [REPEAT] [extra solve options...]
#   bench/stage_times.sh builtin:cornell 5
# Prints one line per rank count: the median seconds of load, mesh, formfactors, solve, write.
set -euo pipefail
cd "$(dirname "$0")/.."
scene=${1:-builtin:cornell}
repeat=${2:-5}
shift $(($# < 2 ? $# : 2))
# Open MPI: as root, and 2 ranks on 1 core (other MPIs ignore these).
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

median() { sort -g | awk '{v[NR]=$1} END {print (NR % 2) ? v[(NR+1)/2] : (v[NR/2] + v[NR/2+1]) / 2}'; }

printf '%-6s %10s %10s %12s %10s %10s %10s\n' ranks load mesh formfactors solve write total
for ranks in 1 2; do
  : >"$work/times"
  for ((i = 0; i < repeat; ++i)); do
    start=$(date +%s.%N)
    mpiexec -n "$ranks" build/radiosity solve "$scene" -o "$work/r.h5" "$@" 2>&1 |
      sed -n 's/.*stage times (s): //p' >>"$work/times"
    awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN {print "total", b - a}' >>"$work/times.total"
  done
  row=()
  for stage in load mesh formfactors solve write; do
    row+=("$(awk -v s="$stage" '{for (i = 1; i < NF; i += 2) if ($i == s) print $(i+1)}' "$work/times" | median)")
  done
  total=$(awk '{print $2}' "$work/times.total" | median)
  rm -f "$work/times.total"
  printf '%-6s %10.4f %10.4f %12.4f %10.4f %10.4f %10.4f\n' "$ranks" "${row[@]}" "$total"
done
