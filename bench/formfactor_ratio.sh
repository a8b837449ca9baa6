#!/usr/bin/env bash
# The form-factor stage against bare Embree on the same rays (bench/formfactor_bench.cpp): the
# median wall time of 9 repetitions of each, interleaved at random, their ratio (bare time /
# stage time: the stage's speed relative to bare Embree; 1 would mean the stage costs nothing
# beyond tracing) and the rays per second of each, for 1 and 2 threads.
# The scene and its size from the environment (bench/formfactor_bench.cpp), e.g. at 10^6 patches:
#   RADIOSITY_BENCH_SCENE='builtin:rooms?patches=1000000' RADIOSITY_BENCH_PATCHES=1000000 \
#   RADIOSITY_BENCH_RAYS=16 bash bench/formfactor_ratio.sh build
# Usage: bench/formfactor_ratio.sh [BUILD_DIR] [extra benchmark options...]
#   bench/formfactor_ratio.sh build
set -euo pipefail
cd "$(dirname "$0")/.."
source bench/common.sh
bench_setup formfactor_bench "$@"

# (BM_TracerBatches, the stage's tracing call alone, only when asked for: --benchmark_filter=.)
medians_csv --benchmark_filter='BM_FormFactorStage|BM_BareEmbree' |
  awk -F, '
    NR == 1 { for (i = 1; i <= NF; ++i) if ($i == "\"rays/s\"") raysColumn = i; next }
    $1 ~ /_median"$/ {
      split($1, part, "/")  # "BM_Name, threads, real_time_median"
      name = substr(part[1], 2); threads = part[2]
      time[name, threads] = $3; unit = $5; rays[name, threads] = $raysColumn; seen[threads] = 1
    }
    END {
      printf "%-8s %14s %14s %14s %14s %8s\n", "threads", "stage " unit, "bare " unit,
             "stage rays/s", "bare rays/s", "ratio"
      for (t = 1; t <= 64; ++t) {
        if (!(t in seen)) continue
        s = time["BM_FormFactorStage", t]; b = time["BM_BareEmbree", t]
        printf "%-8s %14.1f %14.1f %14.3g %14.3g %8.2f\n", t, s, b,
               rays["BM_FormFactorStage", t], rays["BM_BareEmbree", t], (s > 0 ? b / s : 0)
      }
    }'
