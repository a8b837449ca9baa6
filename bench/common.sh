# Sourced by the bench scripts that run a Google Benchmark program of BUILD_DIR/bench/ (not run
# on its own): their arguments, and the runs they share.

# bench_setup NAME [BUILD_DIR] [extra benchmark options...]: sets `program` to
# BUILD_DIR/bench/NAME (BUILD_DIR: build by default) and `options` to the extra options; exits 2
# if NAME was not built.
bench_setup() {
  local name=$1
  shift
  local build=${1:-build}
  shift $(($# < 1 ? $# : 1))
  options=("$@")
  program="$build/bench/$name"
  [[ -x $program ]] || { echo "no $program: build with -DRADIOSITY_BENCH=ON first" >&2; exit 2; }
}

# medians_csv [benchmark options...]: the program's medians (with the other aggregates) of 9
# repetitions interleaved at random, as CSV on stdout; the given options, then the extra ones
# of the command line, come after these and win. Its log on stderr is dropped.
medians_csv() {
  "$program" --benchmark_repetitions=9 --benchmark_enable_random_interleaving=true \
    --benchmark_report_aggregates_only=true --benchmark_format=csv "$@" "${options[@]}" \
    2>/dev/null
}
