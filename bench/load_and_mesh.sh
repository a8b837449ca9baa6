#!/usr/bin/env bash
# Wall time of loading and meshing builtin:rooms, and the peak memory of the process, at
# growing sizes. Runs `radiosity solve --mesh-only` on one process (no form factors, no file).
# Usage: bench/load_and_mesh.sh [PATCHES...]      (default: 100000 1000000 10000000)
# RADIOSITY=path picks the program (default build/radiosity). Needs GNU time (/usr/bin/time,
# Debian package `time`, installed by .ci/setup). Prints one row per size:
#   patches (asked), triangles (made), load s, mesh s, peak RSS MiB.
set -euo pipefail
cd "$(dirname "$0")/.."
sizes=("$@")
((${#sizes[@]} > 0)) || sizes=(100000 1000000 10000000)
[[ -x /usr/bin/time ]] || { echo "needs GNU time: apt-get install time" >&2; exit 2; }
program=${RADIOSITY:-build/radiosity}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
log=$(mktemp)
trap 'rm -f "$log"' EXIT

printf '%-10s %10s %8s %8s %14s\n' patches triangles load_s mesh_s peak_rss_MiB
for n in "${sizes[@]}"; do
  /usr/bin/time -v "$program" solve "builtin:rooms?patches=$n" --mesh-only >"$log" 2>&1
  triangles=$(sed -n 's/^mesh: \([0-9]*\) input triangles.*/\1/p' "$log")
  load=$(sed -n 's/.*stage times (s): load \([^ ]*\) mesh.*/\1/p' "$log")
  mesh=$(sed -n 's/.*stage times (s): load [^ ]* mesh \([^ ]*\).*/\1/p' "$log")
  rss=$(sed -n 's/.*Maximum resident set size (kbytes): //p' "$log")
  printf '%-10s %10s %8.2f %8.2f %14.0f\n' "$n" "$triangles" "$load" "$mesh" "$((rss / 1024))"
done
