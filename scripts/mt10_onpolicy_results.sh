#!/usr/bin/env bash
# Regenerates docs/results/mt10_onpolicy/ (charts, per-task tables, CSV) from
# the three on-policy MT10 run directories docs/results/README.md describes.
# Runs are only read.
#   scripts/mt10_onpolicy_results.sh [RUNS_DIR]   (default runs/)
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-runs}
python3 scripts/results_report.py "$runs/mt10_mtppo_200k" "$runs/mt10_mttrpo_200k" \
  "$runs/mt10_teppo_200k" \
  --out docs/results/mt10_onpolicy --title "MT10 on-policy (manyworlds, seed 1, 200k steps/task)" \
  --reference "MT-PPO (Meta-World paper, max over training)=0.305" \
  --reference "MT-TRPO (Meta-World paper)=0.313" \
  --reference "TE-PPO (Meta-World paper)=0.209"
