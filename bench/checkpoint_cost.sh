#!/usr/bin/env bash
# The cost of checkpointing: one run with --checkpoint (every 0 s: only the final checkpoint, a
# whole write of every row and of B), the same run without, and a restart that reads the
# checkpoint back (stage "done": no sampling, no solve iterations).
# Usage: bench/checkpoint_cost.sh BUILD_DIR SCENE RANKS [solve options...]
#   bash bench/checkpoint_cost.sh build builtin:cornell 2 --patches 100000 --rays 1024
# Prints the file size (total, per patch, per nonzero), the write time (from the program's
# checkpoint line), the wall time of the run with and without the checkpoint, and the restart's.
set -euo pipefail
cd "$(dirname "$0")/.."
build=$1 scene=$2 ranks=$3
shift 3
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
run() {  # run NAME ARGS...: wall seconds of mpiexec
  local name=$1
  shift
  local start end
  start=$(date +%s.%N)
  mpiexec -n "$ranks" "$build/radiosity" solve "$scene" -q "$@" -o "$work/$name.h5" \
    >"$work/$name.log" 2>&1
  end=$(date +%s.%N)
  awk -v a="$start" -v b="$end" 'BEGIN { printf "%.2f", b - a }'
}
plain=$(run plain "$@")
with=$(run with "$@" --checkpoint "$work/ck.h5" --checkpoint-every 0)
restart=$(run restart "$@" --restart "$work/ck.h5")
line=$(grep -m1 'checkpoint: wrote' "$work/with.log")
write=$(sed -nE 's/.*MB, ([0-9.]+) s\).*/\1/p' <<<"$line")
patches=$(sed -nE 's/.*-> ([0-9]+) patches.*/\1/p' "$work/plain.log" | head -n1)
nonzeros=$(sed -nE 's/.* ([0-9]+) nonzeros \(.*/\1/p' "$work/plain.log" | head -n1)
bytes=$(stat -c %s "$work/ck.h5")
echo "| patches | nonzeros | checkpoint MB | bytes/patch | bytes/nonzero | write s | µs/patch | run s without | run s with | restart s (read + write result) |"
echo "|---|---|---|---|---|---|---|---|---|---|"
awk -v p="$patches" -v n="$nonzeros" -v b="$bytes" -v w="$write" -v a="$plain" -v c="$with" \
  -v r="$restart" 'BEGIN {
    printf "| %d | %d | %.1f | %.0f | %.1f | %.2f | %.1f | %s | %s | %s |\n",
           p, n, b / 1e6, b / p, b / n, w, 1e6 * w / p, a, c, r }'
