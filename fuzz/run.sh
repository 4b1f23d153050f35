#!/usr/bin/env bash
# Build (clang, ASan+UBSan+libFuzzer) and run the scene-reader fuzz target.
#   bash fuzz/run.sh [BUILD_DIR] [SECONDS]
# Seeds: every shipped scene (workflows/scenes, bench/scenes) and fuzz/seeds;
# new interesting inputs go to a scratch corpus in BUILD_DIR, never into the
# repository. A crash leaves crash-* / leak-* files in BUILD_DIR and fails.
# Warnings are not errors here: the gcc build (scripts/build.sh) is the
# -Werror gate, and clang warns about other things.
set -euo pipefail
source "$(dirname "$0")/../scripts/env.sh"
BUILD="${1:-$DNAROD_ROOT/build-fuzz}"
SECONDS_TO_RUN="${2:-20}"
command -v clang++ >/dev/null || { echo "fuzz: clang++ not found (Debian package clang; scripts/setup.sh installs it)" >&2; exit 1; }
cmake -S "$DNAROD_ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
      -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
      -DDNAROD_SANITIZE=ON -DDNAROD_FUZZ=ON -DDNAROD_WERROR=OFF \
      -DPython_EXECUTABLE=/usr/bin/python3 > "$BUILD.cmake.log" 2>&1 \
  || { cat "$BUILD.cmake.log"; exit 1; }
JOBS="$(nproc)"; [ "$JOBS" -gt 2 ] && JOBS=2
cmake --build "$BUILD" -j "$JOBS" --target fuzz_scene_reader
corpus="$BUILD/fuzz-corpus"
mkdir -p "$corpus"
seeds=("$DNAROD_ROOT/fuzz/seeds" "$DNAROD_ROOT/workflows/scenes")
[ -d "$DNAROD_ROOT/bench/scenes" ] && seeds+=("$DNAROD_ROOT/bench/scenes")
cd "$BUILD"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
"$BUILD/bin/fuzz_scene_reader" -max_total_time="$SECONDS_TO_RUN" -max_len=4096 -timeout=10 \
    -dict="$DNAROD_ROOT/fuzz/toml.dict" -print_final_stats=1 "$corpus" "${seeds[@]}"
