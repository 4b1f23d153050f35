#!/usr/bin/env bash
# "No silent bad numbers" (docs/reliability.md) at the level of the code itself:
#   1. AddressSanitizer + UndefinedBehaviorSanitizer build of rodcore and its
#      GoogleTest suites (build-asan/, -DDNAROD_SANITIZE=ON), run with CTest.
#      Any leak, out-of-bounds access, use-after-free or undefined behaviour
#      aborts the test that triggers it.
#   2. The libFuzzer target of the scene reader (fuzz/, clang), run briefly
#      from a seed corpus of the shipped scenes: any crash, sanitizer report
#      or exception other than InputError fails.
# Usage: bash scripts/test_sanitize.sh [--no-fuzz] [--fuzz-seconds N]
# Environment: DNAROD_ASAN_BUILD (default build-asan), DNAROD_FUZZ_BUILD
# (default build-fuzz), DNAROD_FUZZ_SECONDS (default 20).
set -euo pipefail
source "$(dirname "$0")/env.sh"
ASAN_BUILD="${DNAROD_ASAN_BUILD:-$DNAROD_ROOT/build-asan}"
FUZZ_BUILD="${DNAROD_FUZZ_BUILD:-$DNAROD_ROOT/build-fuzz}"
FUZZ_SECONDS="${DNAROD_FUZZ_SECONDS:-20}"
fuzz=1
while [ $# -gt 0 ]; do
  case "$1" in
    --no-fuzz) fuzz=0 ;;
    --fuzz-seconds) FUZZ_SECONDS="$2"; shift ;;
    *) echo "test_sanitize.sh: unknown argument '$1' (allowed: --no-fuzz, --fuzz-seconds N)" >&2; exit 2 ;;
  esac
  shift
done
JOBS="$(nproc)"; [ "$JOBS" -gt 2 ] && JOBS=2

echo "== ASan+UBSan build ($ASAN_BUILD)"
cmake -S "$DNAROD_ROOT" -B "$ASAN_BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DDNAROD_SANITIZE=ON \
      -DPython_EXECUTABLE=/usr/bin/python3 > "$ASAN_BUILD.cmake.log" 2>&1 \
  || { cat "$ASAN_BUILD.cmake.log"; exit 1; }
# Only what CTest runs (rodsim and the GoogleTest suites), not the benchmarks.
targets=(rodsim)
for src in "$DNAROD_ROOT"/tests/cpp/test_*.cpp; do targets+=("$(basename "$src" .cpp)"); done
cmake --build "$ASAN_BUILD" -j "$JOBS" --target "${targets[@]}"

echo "== C++ tests under ASan+UBSan (CTest)"
# DNAROD_UNDER_SANITIZER lets the slowest physics tests pick a reduced size
# (they say so in their output); nothing is skipped.
export DNAROD_UNDER_SANITIZER=1
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
ctest --test-dir "$ASAN_BUILD" --output-on-failure -j "$JOBS"

if [ "$fuzz" = 1 ]; then
  echo "== Fuzzing the scene reader for ${FUZZ_SECONDS} s (libFuzzer, clang)"
  bash "$DNAROD_ROOT/fuzz/run.sh" "$FUZZ_BUILD" "$FUZZ_SECONDS"
fi
echo "== sanitizers: all clean"
