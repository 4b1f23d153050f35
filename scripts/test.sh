#!/usr/bin/env bash
# The one test command (README, CI): install, build and install this checkout,
# then every C++ and Python test and the code checks. Exits non-zero if
# anything fails. Each suite prints its wall time; a complete run writes them to
# out/records/test_times.json (scripts/record_run.py; its `commit test_times` makes that
# results/test_times.json, the record docs/testing.md quotes: tracked files stay as they were).
set -euo pipefail
source "$(dirname "$0")/env.sh"
start=$SECONDS
steps=()
# the Debian packages, and GROMACS built for this CPU where Debian's mdrun cannot run
# (scripts/build_gromacs.sh --if-needed: ~15-20 min, else ~1 s)
t0=$SECONDS; bash "$DNAROD_ROOT/scripts/setup.sh"; echo "-- setup: $((SECONDS - t0)) s"
steps+=(--step "setup=$((SECONDS - t0))")
# build.sh also installs (scripts/install.sh): the tests import the installed
# toolkit, and tests/python/test_install.py checks that it is this checkout.
t0=$SECONDS; bash "$DNAROD_ROOT/scripts/build.sh"; echo "-- build + install: $((SECONDS - t0)) s"
steps+=(--step "build + install=$((SECONDS - t0))")
echo "== C++ tests (CTest)"
t0=$SECONDS; ctest --test-dir "$DNAROD_BUILD" --output-on-failure -j "$(nproc)"
echo "-- CTest: $((SECONDS - t0)) s"
steps+=(--step "CTest=$((SECONDS - t0))")
echo "== Python tests (pytest)"
cd "$DNAROD_ROOT"
# -P: the checkout folder is not put on sys.path, so the tests see only the
# installed toolkit (pyproject.toml sets -rs --strict-markers).
t0=$SECONDS; "$PYTHON" -P -m pytest -q tests/python "$@"; echo "-- pytest: $((SECONDS - t0)) s"
steps+=(--step "pytest=$((SECONDS - t0))")
# The same C++ tests under AddressSanitizer + UndefinedBehaviorSanitizer
# (build-asan/), then a short libFuzzer run of the scene reader (build-fuzz/).
# DNAROD_SKIP_SANITIZE=1 leaves them out (say so in any report that uses it).
if [ "${DNAROD_SKIP_SANITIZE:-0}" = 1 ]; then
  echo "== Sanitizers: SKIPPED (DNAROD_SKIP_SANITIZE=1)"
else
  echo "== Sanitizers (scripts/test_sanitize.sh)"
  t0=$SECONDS; bash "$DNAROD_ROOT/scripts/test_sanitize.sh"; echo "-- sanitizers + fuzz: $((SECONDS - t0)) s"
  steps+=(--step "sanitizers + fuzz=$((SECONDS - t0))")
fi
# Format, lint and types (scripts/check.sh), last so a style slip does not hide test results.
t0=$SECONDS; bash "$DNAROD_ROOT/scripts/check.sh"; echo "-- checks: $((SECONDS - t0)) s"
steps+=(--step "checks=$((SECONDS - t0))")
# only a whole run (no pytest selection, sanitizers included) is the figure the docs quote
if [ $# -eq 0 ] && [ "${DNAROD_SKIP_SANITIZE:-0}" != 1 ]; then
  "$PYTHON" "$DNAROD_ROOT/scripts/record_run.py" test-times --total-s $((SECONDS - start)) "${steps[@]}"
fi
