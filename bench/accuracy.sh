#!/usr/bin/env bash
# The measurements of docs/notebook/accuracy-measurements.md (summed up in docs/accuracy.md), all in
# the one error measure of measure/light_error.h (per channel, the area-weighted RMS over the
# reflecting patches of each patch's error relative to its own B, floored at 1 % of the mean B).
#  (a) `radiosity study` against exact answers: the plates with a black emitter and the sphere
#      with an emitting cap, both estimators over the rays; tolerance sweeps on the sphere and
#      on the Cornell box (against a high-effort solve).
#  (b) the Cornell box against the independent path tracer: `solve` (wall time, median of RUNS
#      runs) then `verify` (one run: the result is the same every time) for each estimator and
#      ray count, the default run (no options) and `--target-error 0.01`.
# Usage: bash bench/accuracy.sh BUILD_DIR OUT_DIR [RANKS]
#   bash bench/accuracy.sh build docs/accuracy 2      (about 6 minutes on 2 idle cores)
# Environment: RUNS (3) timed solves per setting, PATHS (131072) and PATCHES (200) for verify.
# Writes OUT_DIR/{plates,sphere5,sphere5_rtol,cornell_rtol}.{csv,svg}, OUT_DIR/cornell_verify.{csv,svg},
# OUT_DIR/logs/ (every solve's and verify's output), and prints the convergence slopes.
# Needs /usr/bin/python3 with h5py (Debian's python3-h5py) for bench/accuracy_cornell.py.
set -euo pipefail
cd "$(dirname "$0")/.."
build=$1 out=$2 ranks=${3:-2}
runs=${RUNS:-3} paths=${PATHS:-131072} patches=${PATCHES:-200}
python=/usr/bin/python3
mkdir -p "$out/logs"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
run() { mpiexec -n "$ranks" "$build/radiosity" "$@"; }
study() { run study "$@" -q >/dev/null; }

# (a) Exact answers. Plates: 256 patches, receiver ρ = 0.5, black emitter (H = E F exactly).
study 'builtin:plates?rho=0.5' --max-area 0.01 --rays 16,64,256,1024,4096 \
  --estimator hemisphere,mis -o "$out/plates.csv" --plot "$out/plates.svg"
# Sphere level 5 (20480 facets), ρ = 0.7, the cap above z = 0.5 r emitting.
sphere='builtin:sphere?rho=0.7&cap=0.5&level=5'
study "$sphere" --rays 16,64,256,1024 --estimator hemisphere,mis \
  -o "$out/sphere5.csv" --plot "$out/sphere5.svg"
study "$sphere" --rays 256 --estimator hemisphere --rtol 1e-1,1e-2,1e-3,1e-4,1e-6,1e-10 \
  -o "$out/sphere5_rtol.csv" --plot "$out/sphere5_rtol.svg"

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# The solver's tolerance on the Cornell box (MIS, 1024 rays), against a high-effort solve of
# the same mesh with its own seed (a reference sharing the studied samples would hide their
# error); this measures sampling and solver error, not the discretisation.
run solve builtin:cornell --estimator mis --rays 16384 --seed 7 --rtol 1e-12 -q \
  -o "$work/reference.h5" >/dev/null
study builtin:cornell --reference "$work/reference.h5" --rays 1024 --estimator mis \
  --rtol 1e-1,1e-2,1e-3,1e-4,1e-6,1e-10 -o "$out/cornell_rtol.csv" --plot "$out/cornell_rtol.svg"

# (b) The Cornell box against verify's path-traced reference (the same patches and paths for
# every setting: same mesh, same --seed).
table=$out/cornell_verify.csv
rm -f "$table"
cornell() {  # cornell LABEL ESTIMATOR RAYS [solve options]
  local label=$1 estimator=$2 rays=$3 name=$1_$3 times=() start end i
  shift 3
  for ((i = 1; i <= runs; ++i)); do
    start=$(date +%s.%N)
    run solve builtin:cornell "$@" -o "$work/$name.h5" >"$out/logs/$name.solve.log" 2>&1
    end=$(date +%s.%N)
    times+=("$(echo "$end - $start" | bc)")
  done
  run verify "$work/$name.h5" --paths "$paths" --patches "$patches" \
    >"$out/logs/$name.verify.log" 2>/dev/null || true
  $python bench/accuracy_cornell.py row "$table" "$label" "$estimator" "$rays" \
    "$work/$name.h5" "$out/logs/$name.verify.log" "${times[@]}"
  echo "cornell $label $rays: ${times[*]} s"
}
for rays in 64 256 1024 4096 16384; do
  cornell hemisphere hemisphere "$rays" --estimator hemisphere --rays "$rays"
done
for rays in 64 256 512 1024 2048 4096; do
  cornell mis mis "$rays" --estimator mis --rays "$rays"
done
cornell default auto 1024                              # no options at all
# The default run once more against a reference with 4x the paths (half its noise): its error
# is near 1 %, where the noise taken out matters.
run verify "$work/default_1024.h5" --paths $((4 * paths)) --patches "$patches" \
  >"$out/logs/default_1024.verify4x.log" 2>/dev/null || true
grep -E "measured|noise|estimate|coverage" "$out/logs/default_1024.verify4x.log"
cornell target-error auto 1024 --target-error 0.01     # rays added until the estimate < 1 %
$python bench/accuracy_cornell.py plot "$table" "$out/cornell_verify.svg"

# Least-squares slope of log(error) against log(rays), per estimator; $1 the CSV, $2 the column.
slopes() {
  awk -F, -v column="$2" '
    NR == 1 { for (i = 1; i <= NF; ++i) { if ($i == column) c = i; if ($i == "estimator") e = i
                                          if ($i == "rays") r = i }; next }
    $e == "auto" { next }
    { k = $e; x = log($r); y = log($c); n[k]++; sx[k] += x; sy[k] += y; sxx[k] += x * x
      sxy[k] += x * y }
    END { for (k in n) printf "  %s %s: slope %.3f\n", column, k,
            (n[k] * sxy[k] - sx[k] * sy[k]) / (n[k] * sxx[k] - sx[k] * sx[k]) }' "$1"
}
echo "plates:"; slopes "$out/plates.csv" B_error_red
echo "sphere level 5:"; slopes "$out/sphere5.csv" B_error_red
echo "cornell (measured, noise taken out; includes the discretisation floor):"
slopes "$table" corrected_red
