#!/usr/bin/env bash
# The halo exchange of a product with F: what each rank receives from the others in one MatMult
# (one channel), for the blocks of patches cut by count along the Morton curve, on several rank
# counts. These are counts, not times: ranks may be oversubscribed.
#
#   bash bench/halo_volume.sh [SCENE] [SAMPLES] [RANKS...]
#   bash bench/halo_volume.sh 'builtin:rooms?patches=100000' 32 2 4 8 16
#
# RADIOSITY (default build/radiosity, from the repository's root) is the program; MPIRUN (default
# mpirun) starts it.
# Per rank count, from PETSc's -mat_view ::ascii_info_detail (the matrix's rows and nonzeros per
# rank, and the VecScatter of its product: "leaves" are the ghost entries of x a rank receives,
# "remote ranks" the ranks it receives from) and -log_view (the MatMult row of the Solve stage:
# calls, messages and their average length, which PETSc prints to two digits):
#   ranks, rows per rank, nonzeros per row (as PETSc counts them: the kept zero diagonal makes it
#   one more than the log's), share of the nonzeros off the rank's diagonal block,
#   ghosts per rank (mean, max) and as a share of the rank's rows, ranks received from (mean, max),
#   messages per product, and bytes per product: exact (8 bytes a ghost, summed over the ranks)
#   and as -log_view counts them (messages x average length / calls).
# The table in docs/notebook/scaling-measurements.md ("Halo exchange per product") was made with it.
set -euo pipefail
cd "$(dirname "$0")/.."

scene=${1:-'builtin:rooms?patches=100000'}
samples=${2:-32}
shift $(( $# >= 2 ? 2 : $# ))
ranks_list=("$@")
[ ${#ranks_list[@]} -gt 0 ] || ranks_list=(2 4 8 16)
radiosity=${RADIOSITY:-build/radiosity}
mpirun=${MPIRUN:-mpirun}

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# Blocks by count, where the program can cut them otherwise (--balance).
balance=()
if "$radiosity" solve --help 2>/dev/null | grep -q -- '--balance'; then balance=(--balance count); fi

echo "scene $scene, $samples samples per patch, blocks by count"
printf '%5s %9s %7s %8s %9s %9s %7s %6s %5s %8s %12s %12s\n' ranks rows/rank nnz/row offdiag \
  ghosts ghost_max ghost/row from from_max msgs/prod bytes/prod log_view
for p in "${ranks_list[@]}"; do
  # shellcheck disable=SC2086
  $mpirun -n "$p" "$radiosity" solve "$scene" --rays "$samples" -q "${balance[@]}" \
    -o "$work/result.h5" -mat_view ::ascii_info_detail -log_view ":$work/log_view.txt" |
    grep -E '^ *\[[0-9]+\] (Local rows|off-diagonal part|Number of roots)' >"$work/mat_view.txt"
  matmult=$(awk '/Event Stage 4: Solve/ {solve = 1} solve && $1 == "MatMult" {print $2, $8, $9; exit}' \
    "$work/log_view.txt")
  awk -v p="$p" -v matmult="$matmult" '
    /Local rows/ { sub(/^ *\[/, ""); r = $1 + 0; rows[r] = $4; nz[r] = $6 }
    /off-diagonal part/ { sub(/^ *\[/, ""); off[$1 + 0] = $5 }
    /Number of roots/ {
      sub(/^ *\[/, ""); r = $1 + 0
      match($0, /leaves=[0-9]+/); leaves[r] = substr($0, RSTART + 7, RLENGTH - 7) + 0
      match($0, /remote ranks=[0-9]+/); from[r] = substr($0, RSTART + 13, RLENGTH - 13) + 0
    }
    END {
      for (r = 0; r < p; ++r) {
        R += rows[r]; N += nz[r]; O += off[r]; L += leaves[r]; F += from[r]
        if (leaves[r] > Lmax) Lmax = leaves[r]
        if (from[r] > Fmax) Fmax = from[r]
      }
      split(matmult, m, " ")
      printf "%5d %9d %7.1f %8.3f %9.0f %9d %7.3f %6.1f %5d %8d %12d %12.3g\n", p, R / p, N / R, O / N,
        L / p, Lmax, L / R, F / p, Fmax, F, 8 * L, m[2] * m[3] / m[1]
    }' "$work/mat_view.txt"
done
