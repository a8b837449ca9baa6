#!/usr/bin/env bash
# Products with F against this machine's memory bandwidth (bench/solve_bandwidth.cpp): medians
# of 9 repetitions, interleaved at random, of a STREAM-like triad and of the products (one
# channel: MatMult; three channels in one pass over F: MatMatMult with 3 columns), their bytes
# per second and its ratio to the triad's, and the channel-products per second.
# Usage: bench/solve_bandwidth.sh [BUILD_DIR] [extra benchmark options...]
set -euo pipefail
cd "$(dirname "$0")/.."
source bench/common.sh
bench_setup solve_bandwidth "$@"

medians_csv |
  awk -F, '
    NR == 1 {
      for (i = 1; i <= NF; ++i) {
        if ($i == "\"bytes/s\"") bytesColumn = i
        if ($i == "\"channel-products/s\"") productsColumn = i
      }
      next
    }
    $1 ~ /_median"$/ {
      split($1, part, "/"); name = substr(part[1], 2)
      bytes[name] = $bytesColumn; products[name] = $productsColumn
    }
    END {
      triad = bytes["BM_Triad"]
      printf "triad (memory bandwidth): %.3g bytes/s\n", triad
      printf "%-36s %14s %14s %22s\n", "product", "bytes/s", "ratio to triad",
             "channel-products/s"
      split("BM_ProductOneChannel BM_ProductThreeChannels BM_ProductThreeChannelsInterleaved",
            names, " ")
      for (k = 1; k <= 3; ++k) {
        n = names[k]
        printf "%-36s %14.3g %14.2f %22.1f\n", substr(n, 4), bytes[n], bytes[n] / triad, products[n]
      }
    }'
