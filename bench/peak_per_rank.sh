#!/usr/bin/env bash
# The peak resident set of every rank of a solve (/usr/bin/time -v around each rank), with the
# log's stage times and the discretisation estimate's seconds, for one build or two against each
# other (runs interleaved, so that the machine's noise falls on both alike).
# Usage: bench/peak_per_rank.sh [RANKS] [REPEATS] [solve arguments...]
#   bench/peak_per_rank.sh 2 3 'builtin:rooms?patches=1000000' --rays 32 --refine-rounds 0 --checkpoint
# RADIOSITY=path/to/radiosity measures another build (default build/radiosity); BEFORE=path adds
# a second build, run before it each time. A bare --checkpoint gets a file in the scratch folder.
# One line per run: build, run, each rank's peak in MiB (as the log's `memory:` line counts),
# then the log's figures.
set -euo pipefail
cd "$(dirname "$0")/.."
ranks=${1:-2}
repeats=${2:-3}
shift $(($# < 2 ? $# : 2))
args=("$@")
[[ ${#args[@]} -gt 0 ]] || args=('builtin:rooms?patches=1000000' --rays 32 --refine-rounds 0 --checkpoint)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for k in "${!args[@]}"; do
  [[ ${args[$k]} == --checkpoint && ( $((k + 1)) -ge ${#args[@]} || ${args[$((k + 1))]} == -* ) ]] &&
    args[$k]="--checkpoint=$work/ck.h5"
done
builds=("${RADIOSITY:-build/radiosity}")
[[ -n ${BEFORE:-} ]] && builds=("$BEFORE" "${builds[@]}")

for ((run = 1; run <= repeats; ++run)); do
  for build in "${builds[@]}"; do
    rm -f "$work"/ck.h5 "$work"/time.*
    # (each rank writes its own /usr/bin/time report, named by its rank)
    mpiexec -n "$ranks" sh -c '/usr/bin/time -v -o "$0/time.${OMPI_COMM_WORLD_RANK:-${PMI_RANK:-0}}" "$@"' \
      "$work" "$build" solve "${args[@]}" -o "$work/r.h5" >"$work/log" 2>&1
    peaks=$(for f in "$work"/time.*; do
      sed -n 's/.*Maximum resident set size (kbytes): \([0-9]*\)/\1/p' "$f"
    done | awk '{ printf "%d ", $1 / 1024 }')
    stages=$(sed -n 's/.*stage times (s): //p' "$work/log")
    estimate=$(sed -n 's/.*discretisation from [0-9]* rays (\([0-9.]* s\)).*/\1/p' "$work/log")
    echo "$build run $run: peak MiB per rank ${peaks}| stages ${stages} | discretisation ${estimate}"
  done
done
