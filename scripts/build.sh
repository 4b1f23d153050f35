#!/usr/bin/env bash
# Configure and build everything into build/ (incremental after the first
# time), then install it (scripts/install.sh), so that `import rodcore`,
# `rodsim` and `dnarod` in any shell are what was just built.
set -euo pipefail
source "$(dirname "$0")/env.sh"
cmake -S "$DNAROD_ROOT" -B "$DNAROD_BUILD" -DCMAKE_BUILD_TYPE=Release \
      -DPython_EXECUTABLE=/usr/bin/python3 "$@" > "$DNAROD_BUILD.cmake.log" 2>&1 \
  || { cat "$DNAROD_BUILD.cmake.log"; exit 1; }
cmake --build "$DNAROD_BUILD" -j "$(nproc)"
bash "$DNAROD_ROOT/scripts/install.sh"
