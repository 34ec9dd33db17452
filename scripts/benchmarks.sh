#!/usr/bin/env bash
# Runs every benchmark behind docs/benchmarks.md on this machine and writes
# the complete output to bench/logs/benchmarks_<date>.log (or the file given as the
# last argument). `--peers-only` runs only the peer comparisons (the last
# section). Needs a Release build in build/ (scripts/test.sh or
# scripts/main.sh makes one). The peer comparisons make their own virtual
# environments (bench/peers/learner_peers.sh, env_throughput.sh: PyPI's torch,
# Stable-Baselines3, Meta-World, EnvPool) and use Debian's python3-torch.
# Takes about 18 minutes on two cores plus about 30 for the peers (more the
# first time: the virtual environments); run it on an otherwise idle machine,
# the figures are medians of repeats but the machine must be quiet.
set -euo pipefail
cd "$(dirname "$0")/.."
peers_only=0
if [ "${1:-}" = "--peers-only" ]; then peers_only=1; shift; fi
log=${1:-bench/logs/benchmarks_$(date -u +%F).log}
B=build/manyworlds
{
  echo "# $(date -u +%FT%TZ) $(git rev-parse --short HEAD)"
  lscpu | grep -E '^(Model name|CPU\(s\)|Vendor ID|CPU family|Model):' || true
  set -x
  if [ "$peers_only" -eq 0 ]; then
    $B bench env --env cartpole --threads 1 --steps 2000000
    for env in mt10 reach push pick-place; do
      $B bench env --env $env --num-envs 16 --threads 1 --steps 20000
      $B bench env --env $env --num-envs 16 --threads 2 --steps 20000
    done
    build/bench/bench_manipulation --benchmark_repetitions=5 \
      --benchmark_report_aggregates_only=true --benchmark_min_time=0.3
    # The DeepMind-Control-style suites' state steps against raw MuJoCo.
    build/bench/bench_dmc --benchmark_repetitions=5 --benchmark_min_time=0.3 \
      --benchmark_enable_random_interleaving=true --benchmark_report_aggregates_only=true
    # OpenBLAS kernels: the ones chosen for this CPU, and the generic ones
    # Debian's OpenBLAS 0.3.21 falls back to on CPUs newer than it knows.
    $B bench agent --tasks 1
    OPENBLAS_CORETYPE=Prescott $B bench agent --tasks 1 --repeats 3
    # Thread layouts for one update: BLAS threads, or data-parallel shards.
    $B bench agent --tasks 1 --blas-threads 1
    $B bench agent --tasks 1 --shards 2
    # The products an update is made of, alone: the ceiling for the above.
    build/bench/bench_gemm --benchmark_repetitions=3 \
      --benchmark_report_aggregates_only=true --benchmark_min_time=0.3
    # The GEMM libraries at those shapes (the products run on oneDNN; docs/benchmarks.md),
    # and an update with the products on OpenBLAS instead.
    build/bench/bench_blas --benchmark_repetitions=5 --benchmark_enable_random_interleaving=true \
      --benchmark_report_aggregates_only=true --benchmark_min_time=0.2
    MANYWORLDS_GEMM=openblas $B bench agent --tasks 1
    for arch in mlp multihead task_encoder moe; do
      $B bench agent --architecture $arch --tasks 10 --disentangled-alpha
    done
    $B bench agent --tasks 10 --disentangled-alpha --pcgrad
    # The MT10 configs' batch: 32 per task.
    $B bench agent --tasks 10 --disentangled-alpha --batch 320 --updates 10
    $B bench agent --tasks 10 --disentangled-alpha --batch 320 --updates 10 --architecture multihead
    # What the published MT10 and MT50 budgets cost here: a few minutes of training at the
    # published batch, projected (about 6 minutes).
    python3 bench/protocol_cost.py --protocol mt10 mt50 --rounds 1 --cli "$B" \
      --json "${log%.log}_protocol_cost.json"
  fi
  # The peers, interleaved, medians over rounds and per-round ratios:
  # SAC update, PPO epoch and PPO training (CartPole, against Stable-Baselines3)
  # against PyTorch in Python with Debian's and PyPI's torch, each at 1 and 2
  # threads; then env steps/s against Meta-World v3 and EnvPool.
  bash bench/peers/learner_peers.sh --rounds 5 --sb3-thread-probe \
    --json "${log%.log}_learner_peers.json"
  bash bench/peers/env_throughput.sh --rounds 3 --json "${log%.log}_env_throughput.json"
} 2>&1 | tee "$log"
