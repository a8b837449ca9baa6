#!/usr/bin/env bash
# Fuzzes the scene loaders (OBJ+MTL, PLY, OFF, STL, .vs3, builtin: specs) with libFuzzer under
# AddressSanitizer and UndefinedBehaviorSanitizer for a bounded time:
#   bash tests/fuzz/run_fuzzer.sh [SECONDS]      (default 60)
# Builds build-fuzz/ with Clang (-DRADIOSITY_FUZZ=ON), starts from a copy of tests/fuzz/corpus
# (new inputs go to a scratch folder, never into the repository) and exits non-zero if anything
# is found: a crash, a sanitizer report, a leak, an exception other than radiosity::Error, an
# input taking longer than 10 s or more than 2 GiB. Reproducers are kept in build-fuzz/findings/.
set -euo pipefail
cd "$(dirname "$0")/../.."

seconds="${1:-60}"
fuzz_dir=tests/fuzz
build_dir=build-fuzz

CC=clang CXX=clang++ cmake -S . -B "$build_dir" -DRADIOSITY_FUZZ=ON \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build "$build_dir" --target scene_loader_fuzzer -j 2

scratch="$(mktemp -d "${TMPDIR:-/tmp}/radiosity-fuzz-corpus.XXXXXX")"
trap 'rm -rf "$scratch"' EXIT
mkdir "$scratch/corpus" "$scratch/files"
cp "$fuzz_dir"/corpus/* "$scratch/corpus"/
export RADIOSITY_FUZZ_TMPDIR="$scratch/files"  # where the fuzzer writes each input as a file
findings="$build_dir/findings"
mkdir -p "$findings"

export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:symbolize=1:detect_stack_use_after_return=1:strict_string_checks=1:check_initialization_order=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export LSAN_OPTIONS="suppressions=$PWD/$fuzz_dir/lsan.supp:print_suppressions=0"

status=0
"$build_dir"/tests/fuzz/scene_loader_fuzzer "$scratch/corpus" \
  -max_total_time="$seconds" -max_len=4096 -timeout=10 -rss_limit_mb=2048 \
  -dict="$fuzz_dir"/obj.dict -artifact_prefix="$findings"/ -print_final_stats=1 \
  || status=$?
if ((status != 0)); then
  echo "scene_loader_fuzzer found a problem (exit $status); reproducer(s) in $findings:" >&2
  ls -l "$findings" >&2
  echo "reproduce with: $build_dir/tests/fuzz/scene_loader_fuzzer $findings/<file>" >&2
  exit 1
fi
echo "scene_loader_fuzzer: nothing found in ${seconds}s"
