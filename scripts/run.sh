#!/usr/bin/env bash
# The main job (README Quickstart, first command): install, build, then the
# scripted rod-vs-MD comparison of the paper's 158-bp DNA scene.
#   bash scripts/run.sh                      # default config, report in out/compare
#   bash scripts/run.sh --config workflows/config/paper.yaml --out out/paper
# Extra arguments go to `dnarod compare`.
set -euo pipefail
source "$(dirname "$0")/env.sh"
start=$SECONDS
bash "$DNAROD_ROOT/scripts/setup.sh"
bash "$DNAROD_ROOT/scripts/build.sh"
cd "$DNAROD_ROOT"
args=("$@")
case " ${args[*]-} " in *" --out "*|*" --output "*|*" -o "*) ;; *) args+=(--out out/compare) ;; esac
case " ${args[*]-} " in *" --cores "*) ;; *) args+=(--cores "$(nproc)") ;; esac
DNAROD_BIN_DIR="$DNAROD_BUILD/bin" dnarod compare "${args[@]}"  # dnarod: installed by build.sh
# The default run is the main job: its time, MD speed and drift go to out/records/main_job.json;
# `scripts/record_run.py commit main_job` makes it results/main_job.json, the record the docs quote
# (a separate step, so that this command leaves every tracked file as it was).
if [ $# -eq 0 ]; then
  "$PYTHON" "$DNAROD_ROOT/scripts/record_run.py" main-job --wall-s $((SECONDS - start)) --out out/compare
fi
echo "Report: $DNAROD_ROOT/out/compare/report/index.html (or the --out you gave)"
