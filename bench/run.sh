#!/usr/bin/env bash
# One command for every benchmark; writes bench/results/*.json and *.png.
#   bench/run.sh           full run (< 20 min on 2 cores)
#   bench/run.sh --quick   coarse sweeps, a few minutes (used to test the scripts)
# Uses $DNAROD_BUILD (default build/), building it first.
set -euo pipefail
source "$(dirname "$0")/../scripts/env.sh"
QUICK=""
[[ "${1:-}" == "--quick" ]] && QUICK="--quick"
OUT="${BENCH_OUT:-$DNAROD_ROOT/bench/results}"
mkdir -p "$OUT"
[[ -n "${BENCH_NO_BUILD:-}" ]] || bash "$DNAROD_ROOT/scripts/build.sh" > /dev/null  # BENCH_NO_BUILD=1: use the build as is
echo "== machine"; nproc; uptime
echo "== RHS / step microbenchmarks (Google Benchmark)"
MINTIME=0.1; [[ -n "$QUICK" ]] && MINTIME=0.02
"$DNAROD_BUILD/bin/rodbench" --benchmark_min_time="$MINTIME" \
  --benchmark_out="$OUT/rhs_bench.json" --benchmark_out_format=json | tail -n +1
echo "== work-precision (P1, P2, P3)"
"$PYTHON" "$DNAROD_ROOT/bench/workprecision.py" --build "$DNAROD_BUILD" --out "$OUT" $QUICK
echo "== stability stress"
"$PYTHON" "$DNAROD_ROOT/bench/stress/stability.py" --build "$DNAROD_BUILD" --out "$OUT" $QUICK
echo "== reduced planar system vs full"
"$PYTHON" "$DNAROD_ROOT/bench/reduced.py" --build "$DNAROD_BUILD" --out "$OUT" $QUICK
echo "== output cost, rod vs MD, cost per point"
"$PYTHON" "$DNAROD_ROOT/bench/costs.py" --build "$DNAROD_BUILD" --rhs-json "$OUT/rhs_bench.json" --out "$OUT" $QUICK
echo "== RHS cost by material kind (diagonal, coupled, per point); BENCH_BASE_BUILD=dir also times a base build"
"$PYTHON" "$DNAROD_ROOT/bench/material.py" --build "$DNAROD_BUILD" --out "$OUT" \
  ${BENCH_BASE_BUILD:+--base-build "$BENCH_BASE_BUILD"} --rounds "$([[ -n "$QUICK" ]] && echo 1 || echo 5)"
echo "== coarse-graining a 600-frame 158-bp trajectory (budget: 30 s)"
"$PYTHON" "$DNAROD_ROOT/bench/coarsegrain.py" --out "$OUT"
echo "== coarse-graining bootstrap: stated errors against the block length (calibration, ~10 s CPU)"
"$PYTHON" "$DNAROD_ROOT/bench/cg_block_length.py" --out "$OUT"
echo "== writhe of a 10.5-kbp ring: exact against coarsened, with the coarsening's error (~15 s CPU per seed)"
"$PYTHON" "$DNAROD_ROOT/bench/topology.py" --out "$OUT" $([[ -n "$QUICK" ]] && echo "--seeds 1")
echo "== done: $OUT"
