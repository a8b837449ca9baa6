#!/usr/bin/env bash
# Iterations, products with F and the median solve-stage time of every --solver on one scene.
# Usage: bench/solver_times.sh BUILD_DIR REPEATS SCENE [solve options...]
#   bash bench/solver_times.sh build 5 builtin:cornell
#   bash bench/solver_times.sh build 5 'builtin:box?rho=0.999' --max-area 0.02 --rays 64
# Runs on 2 ranks; the repetitions of the solvers are interleaved so that the machine's drift
# falls on all of them alike. Prints a markdown table.
set -euo pipefail
cd "$(dirname "$0")/.."
build=$1 repeats=$2 scene=$3
shift 3
[[ -x $build/bench/result_error ]] ||
  { echo "no $build/bench/result_error: build with -DRADIOSITY_BENCH=ON" >&2; exit 2; }
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
solvers=(jacobi gauss-seidel gmres cg chebyshev southwell)
for ((r = 0; r < repeats; ++r)); do
  for solver in "${solvers[@]}"; do
    if mpiexec -n 2 "$build/radiosity" solve "$scene" --solver "$solver" -q "$@" \
      -o "$work/$solver.h5" >"$work/$solver.log" 2>&1 </dev/null; then
      "$build/bench/result_error" "$work/$solver.h5" --exact 1 >>"$work/$solver.tsv"
    else
      echo "exit $?" >>"$work/$solver.failed"
    fi
  done
done
echo "| solver | iterations | products with F | solve s (median of $repeats) |"
echo "|---|---|---|---|"
for solver in "${solvers[@]}"; do
  if [[ -s $work/$solver.failed ]]; then
    echo "| $solver | $(grep -m1 -o 'did not converge[^(]*' "$work/$solver.log" || tail -n1 "$work/$solver.log") | | |"
    continue
  fi
  sort -t$'\t' -k2,2g "$work/$solver.tsv" | awk -F'\t' -v s="$solver" '
    { t[NR] = $2; it = $1; p = $6 }
    END { m = (NR % 2) ? t[(NR + 1) / 2] : (t[NR / 2] + t[NR / 2 + 1]) / 2
          printf "| %s | %d | %d | %.3f |\n", s, it, p, m }'
done
