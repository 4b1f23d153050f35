#!/usr/bin/env bash
# The one test command (README, CI): install, build, then every C++ and
# Python test. Exits non-zero if anything fails.
set -euo pipefail
source "$(dirname "$0")/env.sh"
bash "$DNAROD_ROOT/scripts/setup.sh"
bash "$DNAROD_ROOT/scripts/build.sh"
echo "== C++ tests (CTest)"
ctest --test-dir "$DNAROD_BUILD" --output-on-failure -j "$(nproc)"
echo "== Python tests (pytest)"
cd "$DNAROD_ROOT"
"$PYTHON" -m pytest -q tests/python "$@"
