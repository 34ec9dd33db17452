#!/usr/bin/env bash
# Regenerates docs/results/mt10/ (charts, per-task tables, CSV) from the two
# MT10 reruns on the faithful tasks that the results page describes, with the
# earlier runs (rewards of 2026-11-23, docs/results/mt10_old_rewards/) drawn
# dashed beside them. Runs are only read; further options go to
# scripts/results_report.py (e.g. --up-to 200000).
#   scripts/mt10_results.sh [RUNS_DIR] [REPORT_OPTIONS...]   (default runs/)
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-runs}
shift || true
python3 scripts/results_report.py "$runs/mt10_mtsac_v3" "$runs/mt10_multihead_v3" \
  --out docs/results/mt10 --title "MT10 (manyworlds, seed 1)" \
  --history docs/results/mt10_old_rewards/results.csv \
  --reference "MT-SAC @500K (CARE paper)=0.38" \
  --reference "multi-head SAC @500K (CARE paper)=0.44" "$@"
