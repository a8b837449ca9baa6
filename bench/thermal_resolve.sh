#!/usr/bin/env bash
# One F, many solves: the wall time of a thermal run that samples F (with --checkpoint) against
# runs that take F from that checkpoint with other temperatures (--formfactors-from), on the
# same ranks; the medians and their ratio, with each run's stage times.
# Usage: bench/thermal_resolve.sh [RANKS] [REPEATS] [SCENE] [solve arguments...]
#   bench/thermal_resolve.sh 2 3 'builtin:rooms?patches=100000' --rays 256
# The boundary conditions name the rooms' surfaces (floor, ceiling, wall, door, light, table,
# shelf); another scene needs a [default] that covers it, which the files here give.
# RADIOSITY=path/to/radiosity measures another build (default build/radiosity).
set -euo pipefail
cd "$(dirname "$0")/.."
ranks=${1:-2}
repeats=${2:-3}
scene=${3:-builtin:rooms?patches=100000}
shift $(($# < 3 ? $# : 3))
args=("$@")
radiosity=${RADIOSITY:-build/radiosity}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cat >"$work/first.toml" <<'TOML'
[surface.floor]
emissivity = 0.9
temperature = 295
[surface.light]
emissivity = 0.8
temperature = 330
[surface.wall]
emissivity = 0.9
heat_flux = 0
[default]
emissivity = 0.85
temperature = 300
TOML
sed -e 's/temperature = 295/temperature = 290/' -e 's/temperature = 330/temperature = 360/' \
  "$work/first.toml" >"$work/second.toml"

seconds() {  # the wall seconds of a run, its log kept
  local start end
  start=$(date +%s.%N)
  if ! mpiexec -n "$ranks" "$radiosity" solve "$scene" "${args[@]}" "$@" >"$work/log" 2>&1; then
    cat "$work/log" >&2  # (as root, Open MPI needs OMPI_ALLOW_RUN_AS_ROOT=1 and ..._CONFIRM=1)
    exit 1
  fi
  end=$(date +%s.%N)
  echo "$end - $start" | bc
}
median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2 ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2) }'; }

: >"$work/first.times"
: >"$work/again.times"
for ((run = 1; run <= repeats; ++run)); do
  rm -f "$work/base.ckpt"
  t=$(seconds --thermal "$work/first.toml" --checkpoint "$work/base.ckpt" -o "$work/first.h5")
  echo "$t" >>"$work/first.times"
  echo "run $run, F sampled:     $t s | $(sed -n 's/.*stage times (s): //p' "$work/log")"
  t=$(seconds --thermal "$work/second.toml" --formfactors-from "$work/base.ckpt" -o "$work/again.h5")
  echo "$t" >>"$work/again.times"
  echo "run $run, F from it:     $t s | $(sed -n 's/.*stage times (s): //p' "$work/log")"
done
first=$(median <"$work/first.times")
again=$(median <"$work/again.times")
echo "median: first $first s, again $again s, ratio $(echo "scale=3; $again / $first" | bc)"
