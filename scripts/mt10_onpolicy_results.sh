#!/usr/bin/env bash
# Regenerates docs/results/mt10_onpolicy/ (charts, per-task tables, CSV) from
# the on-policy MT10 reruns on the faithful tasks that docs/results/README.md
# describes (MT-PPO, MT-TRPO, TE-PPO, seeds 1-3), with the earlier seed-1 runs
# (rewards before 2026-11-24, docs/results/mt10_onpolicy_old_rewards/) drawn
# dashed beside them. Runs are only read; further options go to
# scripts/results_report.py.
#   scripts/mt10_onpolicy_results.sh [RUNS_DIR] [REPORT_OPTIONS...]   (default runs/)
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-runs}
shift || true
dirs=()
for algo in mtppo mttrpo teppo; do
  dirs+=("$runs/mt10_${algo}_v3" "$runs/mt10_${algo}_v3_seed2" "$runs/mt10_${algo}_v3_seed3")
done
python3 scripts/results_report.py "${dirs[@]}" \
  --out docs/results/mt10_onpolicy --title "MT10 on-policy (manyworlds, seeds 1-3)" \
  --history docs/results/mt10_onpolicy_old_rewards/results.csv \
  --reference "MT-PPO (Meta-World paper, max over training)=0.305" \
  --reference "MT-TRPO (Meta-World paper)=0.313" \
  --reference "TE-PPO (Meta-World paper)=0.209" "$@"
