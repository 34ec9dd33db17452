#!/usr/bin/env bash
# Regenerates docs/results/mt10/ (charts, per-task tables, CSV) from the two
# MT10 run directories the results page describes. Runs are only read.
#   scripts/mt10_results.sh [RUNS_DIR]   (default runs/)
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-runs}
python3 scripts/results_report.py "$runs/mt10_mtsac" "$runs/mt10_multihead" \
  --out docs/results/mt10 --title "MT10 (manyworlds, seed 1)" \
  --reference "MT-SAC @500K (CARE paper)=0.38" \
  --reference "multi-head SAC @500K (CARE paper)=0.44"
