#!/usr/bin/env bash
# Contacts cut into the mesh (docs/notebook/accuracy-measurements.md, "Contacts"): the error of the
# default run on the Cornell box against the independent path tracer (`verify`), with its floor as
# published (one quad running under the blocks) and as cut by hand, meshed as given (--contacts off:
# uniform) and with contacts (the default: cut, refined along contact lines, hidden patches left
# out); then builtin:rooms refined to 10^5 patches, uniform and along contacts; then the cost of
# finding and cutting contacts on a scene of 10^6 triangles (--mesh-only).
# Usage: bash bench/contacts.sh BUILD_DIR OUT_DIR [RANKS]
#   bash bench/contacts.sh build docs/accuracy 2      (about 20 minutes on 2 idle cores)
# Environment: RUNS (3) timed solves per setting (median wall time), PATHS (65536) and PATCHES
# (1000) for verify (many patches, as a few at contacts dominate the RMS; the reference's noise,
# about 0.6 %, is taken out in quadrature), BIG (builtin:rooms?patches=1000000) the large scene.
# Writes OUT_DIR/contacts.csv (a row per setting and channel) and OUT_DIR/logs/contacts_*.
set -euo pipefail
cd "$(dirname "$0")/.."
build=$1 out=$2 ranks=${3:-2}
runs=${RUNS:-3} paths=${PATHS:-65536} patches=${PATCHES:-1000}
big=${BIG:-builtin:rooms?patches=1000000}
mkdir -p "$out/logs"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
run() { mpiexec -n "$ranks" "$build/radiosity" "$@"; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# The median of the wall times (s) of RUNS solves; the last run's result stays in $2.
median_solve() {
  local name=$1 result=$2
  shift 2
  local times=()
  for ((k = 0; k < runs; ++k)); do
    local start end
    start=$(date +%s.%N)
    run solve "$@" -o "$result" >"$out/logs/contacts_${name}_solve.txt" 2>&1
    end=$(date +%s.%N)
    times+=("$(awk -v a="$start" -v b="$end" 'BEGIN {printf "%.2f", b - a}')")
  done
  printf '%s\n' "${times[@]}" | sort -g | awk '{a[NR] = $1} END {print a[int((NR + 1) / 2)]}'
}

csv="$out/contacts.csv"
echo "setting,patches,hidden,wall_s,channel,measured,reference_noise,measured_noise_out,estimate,estimate_over_measured,coverage" >"$csv"
for setting in "published_as_given|builtin:cornell?cut_floor=0|--contacts off" \
               "published_cut|builtin:cornell?cut_floor=0|" \
               "hand_cut_as_given|builtin:cornell|--contacts off" \
               "hand_cut|builtin:cornell|"; do
  IFS='|' read -r name scene options <<<"$setting"
  # shellcheck disable=SC2086  # options are words
  wall=$(median_solve "$name" "$work/$name.h5" "$scene" $options)
  log="$out/logs/contacts_${name}_solve.txt"
  count=$(grep -o -- '-> [0-9]* patches' "$log" | grep -o '[0-9]*')
  hidden=$(grep -o 'hidden: [0-9]* patches' "$log" | grep -o '[0-9]*' || echo 0)
  run verify "$work/$name.h5" --patches "$patches" --paths "$paths" --tol 1 \
    >"$out/logs/contacts_${name}_verify.txt" 2>&1
  awk -v name="$name" -v count="$count" -v hidden="$hidden" -v wall="$wall" '
    /measured \(result against reference\)/ {for (c = 0; c < 3; ++c) m[c] = $(NF - 2 + c)}
    /reference noise/ {for (c = 0; c < 3; ++c) n[c] = $(NF - 2 + c)}
    /measured, noise taken out/ {for (c = 0; c < 3; ++c) o[c] = $(NF - 2 + c)}
    /own estimate of its error/ {for (c = 0; c < 3; ++c) e[c] = $(NF - 2 + c)}
    /estimate \/ measured/ {for (c = 0; c < 3; ++c) r[c] = $(NF - 2 + c)}
    /coverage/ {for (c = 0; c < 3; ++c) v[c] = $(NF - 5 + 2 * c)}
    END {
      split("red green blue", channel, " ")
      for (c = 0; c < 3; ++c)
        print name "," count "," hidden "," wall "," channel[c + 1] "," m[c] "," n[c] "," o[c] \
              "," e[c] "," r[c] "," v[c]
    }' "$out/logs/contacts_${name}_verify.txt" >>"$csv"
  echo "$name: $count patches ($hidden hidden), ${wall} s wall (median of $runs)"
done
column -s, -t "$csv"

# Rooms refined from ROOMS_SCENE to ROOMS_PATCHES patches, uniform (--contacts off) against
# refined along contacts (the default; the contact bands take their patches from the rest, as
# --patches keeps the count), each against `verify`.
rooms=${ROOMS_SCENE:-builtin:rooms?patches=25000} rooms_patches=${ROOMS_PATCHES:-100000}
for setting in "rooms_uniform|--contacts off" "rooms_contacts|"; do
  IFS='|' read -r name options <<<"$setting"
  # shellcheck disable=SC2086
  run solve "$rooms" --patches "$rooms_patches" $options -o "$work/$name.h5" \
    >"$out/logs/contacts_${name}_solve.txt" 2>&1
  run verify "$work/$name.h5" --patches "$patches" --paths "$paths" --tol 1 \
    >"$out/logs/contacts_${name}_verify.txt" 2>&1
  echo "$name: $(grep -o -- '-> [0-9]* patches' "$out/logs/contacts_${name}_solve.txt")"
  grep -E 'measured, noise taken out|own estimate|reference noise' \
    "$out/logs/contacts_${name}_verify.txt"
done

# The cost of contacts on 10^6 triangles: load and mesh only, with and without.
for options in "--contacts off" ""; do
  # shellcheck disable=SC2086
  /usr/bin/time -v "$build/radiosity" solve "$big" --mesh-only $options \
    >"$out/logs/contacts_big.txt" 2>&1
  echo "$big ${options:---contacts cut}: $(grep -E '^contacts:|^mesh:|stage times' \
    "$out/logs/contacts_big.txt" | tr '\n' ' ')"
  grep -E 'Maximum resident|Elapsed' "$out/logs/contacts_big.txt"
done
