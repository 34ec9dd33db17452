#!/usr/bin/env bash
# The meta-RL results of docs/results/README.md at the two-core budgets stated
# there: each published config, run with fewer steps, then meta-tested.
# Usage: scripts/meta_rl_budget_runs.sh [NAME ...]   (default: all, in order)
# Each run lives in runs/budget/NAME; a run that was interrupted resumes.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=build/manyworlds
declare -A config overrides
add() { config[$1]=$2; overrides[$1]=$3; order+=("$1"); }
order=()
add ml1_reach_rl2   configs/ml1_reach_rl2.yaml   "experiment.steps_per_task=100000 experiment.eval_every=50000"
add ml1_reach_maml  configs/ml1_reach_maml.yaml  "experiment.steps_per_task=100000 experiment.eval_every=50000"
add ml1_reach_pearl configs/ml1_reach_pearl.yaml "experiment.steps_per_task=20000 experiment.eval_every=10000 experiment.warmup_steps=2000 agent.updates_per_iteration=100"
add ml10_rl2   configs/ml10_rl2.yaml   "experiment.steps_per_task=20000 experiment.eval_every=10000"
add ml10_maml  configs/ml10_maml.yaml  "experiment.steps_per_task=20000 experiment.eval_every=10000"
add ml10_pearl configs/ml10_pearl.yaml "experiment.steps_per_task=6000 experiment.eval_every=3000 experiment.warmup_steps=2000 agent.updates_per_iteration=100"
add ml1_push_rl2    configs/ml1_reach_rl2.yaml   "env.options.task=push eval_env.options.task=push experiment.steps_per_task=50000 experiment.eval_every=25000"
add ml1_push_maml   configs/ml1_reach_maml.yaml  "env.options.task=push eval_env.options.task=push experiment.steps_per_task=50000 experiment.eval_every=25000"
add ml1_push_pearl  configs/ml1_reach_pearl.yaml "env.options.task=push eval_env.options.task=push experiment.steps_per_task=10000 experiment.eval_every=5000 experiment.warmup_steps=2000 agent.updates_per_iteration=100"
add ml1_pick_place_rl2   configs/ml1_reach_rl2.yaml   "env.options.task=pick-place eval_env.options.task=pick-place experiment.steps_per_task=50000 experiment.eval_every=25000"
add ml1_pick_place_maml  configs/ml1_reach_maml.yaml  "env.options.task=pick-place eval_env.options.task=pick-place experiment.steps_per_task=50000 experiment.eval_every=25000"
add ml1_pick_place_pearl configs/ml1_reach_pearl.yaml "env.options.task=pick-place eval_env.options.task=pick-place experiment.steps_per_task=10000 experiment.eval_every=5000 experiment.warmup_steps=2000 agent.updates_per_iteration=100"
add ml10_maml_150k configs/ml10_maml.yaml "experiment.steps_per_task=150000 experiment.eval_every=50000"
add cheetah_vel_pearl configs/cheetah_vel_pearl.yaml "experiment.steps_per_task=10000 experiment.eval_every=2500"

names=("$@"); [ ${#names[@]} -eq 0 ] && names=("${order[@]}")
mkdir -p runs/budget
threads=${THREADS:-1}
for name in "${names[@]}"; do
  [ -n "${config[$name]:-}" ] || { echo "unknown run '$name'; known: ${order[*]}" >&2; exit 2; }
  dir=runs/budget/$name
  if [ -f "$dir.meta_test.json" ]; then echo "$name: done before" >&2; continue; fi
  echo "$name: $(date -u +%FT%TZ) start" >&2
  if [ -f "$dir/summary.json" ]; then
    :  # trained; only the meta-test is missing
  elif [ -f "$dir/config.yaml" ]; then
    "$bin" train --resume "$dir" >>"$dir.log" 2>&1
  else
    # shellcheck disable=SC2086
    "$bin" train "${config[$name]}" ${overrides[$name]} experiment.num_threads=$threads \
        experiment.run_dir="$dir" >"$dir.log" 2>&1
  fi
  "$bin" eval "$dir" --protocol meta-test --json >"$dir.meta_test.json"
  echo "$name: $(date -u +%FT%TZ) done" >&2
done
