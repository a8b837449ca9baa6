#!/usr/bin/env bash
# Stability of every --solver on stiff and extreme cases (the table of docs/stability.md): each
# case × solver is solved once on 2 ranks and compared with the exact answer (or, for the Cornell
# box, with a GMRES reference at --rtol 1e-14 on the same F).
# Usage: bench/stability.sh [BUILD_DIR]      (default: build; needs BUILD_DIR/bench/result_error)
#   bench/stability.sh build
# Prints a markdown table on stdout and nothing else; the run logs go to a temporary folder that
# is removed at the end. One run per cell: the solve times are single noisy samples.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
radiosity="$build/radiosity"
result_error="$build/bench/result_error"
[[ -x $radiosity ]] || { echo "no $radiosity: build first" >&2; exit 2; }
[[ -x $result_error ]] || { echo "no $result_error: build with -DRADIOSITY_BENCH=ON" >&2; exit 2; }
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

solvers=(jacobi gauss-seidel gmres cg chebyshev southwell)
run=0
notes=()

# solve NAME SCENE OPTIONS...: runs one solve into $work/NAME.h5 (log $work/NAME.log), sets $code.
solve() {
  local name=$1 scene=$2
  shift 2
  if mpiexec -n 2 "$radiosity" solve "$scene" -q -o "$work/$name.h5" "$@" \
    >"$work/$name.log" 2>&1 </dev/null; then
    code=0
  else
    code=$?
  fi
}

# row CASE SOLVER COMPARE SCENE OPTIONS...: one table row. COMPARE is "--exact VALUE" or
# "--reference FILE" (one word each, split here).
row() {
  local label=$1 solver=$2 compare=$3 scene=$4
  shift 4
  run=$((run + 1))
  local name="run$run"
  solve "$name" "$scene" --solver "$solver" "$@"
  local numbers=""
  if ((code == 0)); then
    # shellcheck disable=SC2086  # $compare is two words on purpose
    numbers=$("$result_error" "$work/$name.h5" $compare 2>>"$work/$name.log") || numbers=""
  fi
  if [[ -n $numbers ]]; then
    # iterations, solve s, residual, error, bound, products
    awk -F'\t' -v c="$label" -v s="$solver" -v x="$code" '{
      printf "| %s | %s | %s | %d | %d | %.3g | %.1e | %.1e | %.1e |\n",
             c, s, x, $1, $6, $2, $3, $4, $5 }' <<<"$numbers"
    return
  fi
  # No result: the iteration cap (exit 4, "did not converge ... after N iterations" or "within
  # N batches") shows as "cap N" with the residual reached; anything else is noted below.
  local message iterations residual
  message=$(grep -m1 'radiosity: error' "$work/$name.log" || grep -m1 -i error "$work/$name.log" ||
    true)
  iterations=$(sed -nE 's/.*(after|within) ([0-9]+) (iterations|batches).*/\2/p' <<<"$message")
  residual=$(sed -nE 's/.*relative residual ([0-9.eE+-]+).*/\1/p' <<<"$message")
  if ((code == 4)) && [[ -n $iterations ]]; then
    printf '| %s | %s | %s | cap %s | — | — | %s | — | — |\n' "$label" "$solver" "$code" \
      "$iterations" "${residual:-—}"
  else
    notes+=("$label, $solver (exit $code): ${message:-$(tail -n1 "$work/$name.log")}")
    printf '| %s | %s | %s | fail | — | — | — | — | — |\n' "$label" "$solver" "$code"
  fi
}

# every_solver CASE COMPARE SCENE OPTIONS...: a row per solver of $solvers.
every_solver() {
  local label=$1 compare=$2 scene=$3
  shift 3
  for solver in "${solvers[@]}"; do
    row "$label" "$solver" "$compare" "$scene" "$@"
  done
}

# box_exact E RHO: B of a closed box of uniform E and ρ, E/(1 − ρ), to all its digits.
box_exact() {
  awk -v e="$1" -v r="$2" 'BEGIN { printf "%.17g", e / (1 - r) }'
}

echo '| case | solver | exit | iterations | products with F | solve s | residual | error vs exact | bound |'
echo '|---|---|---|---|---|---|---|---|---|'

# Closed box: B = 1/(1 − ρ) on every patch and channel.
for rho in 0.9 0.99 0.999 0.9999; do
  every_solver "box ρ=$rho" "--exact $(box_exact 1 "$rho")" "builtin:box?rho=$rho&e=1" \
    --max-area 0.02 --rays 64
done

# Closed box lit by one face: uniform E is an eigenvector of F, so the cases above are one step
# for a Krylov method; light from one face must bounce ~1/(1 − ρ) times. With a reciprocal F
# (--reciprocity for every solver) the power balances exactly: Σ A B = Σ A E / (1 − ρ).
one_face_box() {  # writes $work/face$1.obj + .mtl: unit cube, normals in, face y = 0 emits
  local rho=$1 obj="$work/face$1.obj"
  {
    echo "mtllib face$rho.mtl"
    for i in 0 1 2 3 4 5 6 7; do echo "v $((i & 1)) $(((i >> 1) & 1)) $(((i >> 2) & 1))"; done
    echo "usemtl wall"
    echo "f 1 2 4 3"; echo "f 5 7 8 6"; echo "f 3 4 8 7"; echo "f 1 3 7 5"; echo "f 2 6 8 4"
    echo "usemtl light"
    echo "f 1 5 6 2"
  } >"$obj"
  printf 'newmtl wall\nKd %s %s %s\nnewmtl light\nKd %s %s %s\nKe 1 1 1\n' \
    "$rho" "$rho" "$rho" "$rho" "$rho" "$rho" >"$work/face$rho.mtl"
  echo "$obj"
}
for rho in 0.9 0.99 0.999 0.9999; do
  every_solver "one-face box ρ=$rho" "--power-balance $rho" "$(one_face_box "$rho")" \
    --max-area 0.01 --rays 32 --reciprocity
done

# Extreme emission: B = E/(1 − 0.9).
for e in 1e-30 1e30; do
  every_solver "box ρ=0.9 E=$e" "--exact $(box_exact "$e" 0.9)" "builtin:box?rho=0.9&e=$e" \
    --max-area 0.05 --rays 16
done

# Extreme scale: ρ 0.5, E 1, B = 2; area bounds scaled with size² (5e-11 vs 5e5).
for scale in "1e-4 5e-11" "1e4 5e5"; do
  read -r size area <<<"$scale"
  every_solver "box size=$size" "--exact 2" "builtin:box?size=$size" --max-area "$area" --rays 64
done

# Cornell box against a GMRES reference at --rtol 1e-14 on the same F: with --reciprocity for
# every solver, and without it for the solvers that do not need it.
for variant in reciprocity plain; do
  extra=()
  label="cornell"
  list=(jacobi gauss-seidel gmres southwell)
  if [[ $variant == reciprocity ]]; then
    extra=(--reciprocity)
    label="cornell --reciprocity"
    list=("${solvers[@]}")
  fi
  solve "ref-$variant" builtin:cornell --rays 256 --solver gmres --rtol 1e-14 "${extra[@]}"
  if ((code != 0)); then
    notes+=("$label: the reference run (gmres --rtol 1e-14) failed with exit $code: $(tail -n1 "$work/ref-$variant.log")")
  fi
  for solver in "${list[@]}"; do
    row "$label" "$solver" "--reference $work/ref-$variant.h5" builtin:cornell \
      --rays 256 "${extra[@]}"
  done
done

if ((${#notes[@]} > 0)); then
  echo
  for note in "${notes[@]}"; do echo "- $note"; done
fi
