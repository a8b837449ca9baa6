#!/usr/bin/env bash
# The measurements of docs/accuracy.md: `radiosity study` on the plates, the sphere with an
# emitting cap and the Cornell box (against a high-effort reference solve), with the fitted
# convergence order of each estimator.
# Usage: bash bench/accuracy.sh BUILD_DIR OUT_DIR [RANKS]
#   bash bench/accuracy.sh build docs/accuracy 2      (about 5 minutes on 2 cores)
# Writes OUT_DIR/{plates,sphere3,sphere4,cornell,cornell_rtol}.{csv,svg} and prints the slopes.
set -euo pipefail
cd "$(dirname "$0")/.."
build=$1 out=$2 ranks=${3:-2}
mkdir -p "$out"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
study() { mpiexec -n "$ranks" "$build/radiosity" study "$@" -q >/dev/null; }

study builtin:plates --max-area 0.01 --rays 16,64,256,1024,4096,16384 \
  -o "$out/plates.csv" --plot "$out/plates.svg"
for level in 3 4; do
  study "builtin:sphere?rho=0.7&cap=0.5&level=$level" --rays 16,64,256,1024,4096 \
    -o "$out/sphere$level.csv" --plot "$out/sphere$level.svg"
done
reference=$(mktemp --suffix=.h5)
trap 'rm -f "$reference"' EXIT
# Its own seed: a reference sharing the studied settings' samples would hide their error.
mpiexec -n "$ranks" "$build/radiosity" solve builtin:cornell --estimator mis --rays 32768 --seed 7 \
  --rtol 1e-12 -q -o "$reference" >/dev/null
study builtin:cornell --reference "$reference" --rays 16,64,256,1024,4096 \
  -o "$out/cornell.csv" --plot "$out/cornell.svg"
study builtin:cornell --reference "$reference" --rays 1024 --estimator mis \
  --rtol 1e-1,1e-2,1e-3,1e-4,1e-6,1e-10 -o "$out/cornell_rtol.csv" --plot "$out/cornell_rtol.svg"

# Least-squares slope of log(error) against log(rays), per estimator; $1 the CSV, $2 the column.
slopes() {
  awk -F, -v column="$2" '
    NR == 1 { for (i = 1; i <= NF; ++i) if ($i == column) c = i; next }
    { e = $4; x = log($5); y = log($c); n[e]++; sx[e] += x; sy[e] += y; sxx[e] += x * x; sxy[e] += x * y }
    END { for (e in n) printf "  %s %s: slope %.3f\n", column, e,
            (n[e] * sxy[e] - sx[e] * sy[e]) / (n[e] * sxx[e] - sx[e] * sx[e]) }' "$1"
}
echo "plates:"; slopes "$out/plates.csv" H_rms_red
echo "sphere level 3:"; slopes "$out/sphere3.csv" B_rms_red
echo "sphere level 4:"; slopes "$out/sphere4.csv" B_rms_red
echo "cornell:"; slopes "$out/cornell.csv" B_rms_red
