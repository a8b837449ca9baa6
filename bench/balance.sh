#!/usr/bin/env bash
# How even the ranks' work is with blocks cut by count and by measured cost (--balance): per
# rank the form-factor stage's CPU seconds (sampling only, the process's CPU clock: right when
# ranks share cores) and the nonzeros of its rows, max/mean over the ranks, from the log's
# "balance:" lines; medians of REPEAT runs.
# Usage: bench/balance.sh SCENE RANKS [REPEAT] [extra solve options...]
#   bench/balance.sh builtin:cornell 8 3
#   bench/balance.sh 'builtin:rooms?patches=40000' 8 3 --rays 256
# Prints per split: CPU max/mean, nonzeros max/mean, the pilot's prediction and its time, and
# the form-factor stage's wall time (the slowest rank's).
set -euo pipefail
cd "$(dirname "$0")/.."
scene=$1
ranks=$2
repeat=${3:-3}
shift $(($# < 3 ? $# : 3))
# Open MPI: as root, and more ranks than cores (other MPIs ignore these).
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

median() {
  sort -g | awk '{v[NR]=$1} END {if (!NR) print "-"; else print (NR % 2) ? v[(NR+1)/2] : (v[NR/2] + v[NR/2+1]) / 2}'
}

printf '%-6s %6s %8s %10s %10s %9s %8s %8s\n' split ranks cpu nonzeros predicted by-count pilot-s ff-s
for split in count cost; do
  : >"$work/runs"
  for ((i = 0; i < repeat; ++i)); do
    mpiexec -n "$ranks" build/radiosity solve "$scene" --balance "$split" -o "$work/r.h5" "$@" \
      >"$work/log"
    cpu=$(sed -n 's/.*CPU time max\/mean \([0-9.]*\).*/\1/p' "$work/log")
    nz=$(sed -n 's/.*nonzeros max\/mean \([0-9.]*\).*/\1/p' "$work/log")
    predicted=$(sed -n 's/.*predicted max\/mean \([0-9.]*\) (by count \([0-9.]*\)).*/\1 \2/p' "$work/log")
    pilot=$(sed -n 's/.*; pilot \([0-9.e+-]*\) s.*/\1/p' "$work/log")
    ff=$(sed -n 's/.*stage times (s):.* formfactors \([0-9.e+-]*\).*/\1/p' "$work/log")
    echo "$cpu $nz ${predicted:-- -} ${pilot:--} $ff" >>"$work/runs"
  done
  row=()
  for column in 1 2 3 4 5 6; do
    row+=("$(awk -v c="$column" '$c != "-" {print $c}' "$work/runs" | median)")
  done
  printf '%-6s %6s %8s %10s %10s %9s %8s %8s\n' "$split" "$ranks" "${row[@]}"
done
