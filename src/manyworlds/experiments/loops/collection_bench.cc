#include "manyworlds/experiments/loops/collection_bench.h"

#include <torch/torch.h>

#include <algorithm>
#include <chrono>
#include <memory>
#include <random>

#include "manyworlds/core/error.h"
#include "manyworlds/core/median.h"
#include "manyworlds/core/rng.h"
#include "manyworlds/envs/all.h"
#include "manyworlds/experiments/algorithm.h"
#include "manyworlds/experiments/loops/collector.h"

namespace manyworlds::experiments {
namespace {

}  // namespace

CollectionBenchResult MeasureCollection(const TrainConfig& config, int repeats) {
  if (repeats < 1) throw ConfigError("bench collect: --repeats must be >= 1");
  config.Validate();
  const Registry& registry = DefaultRegistry();
  const TaskSet tasks = ResolveTasks(config.env, registry);
  Collector collector(tasks, registry, config.env.envs_per_task, config.experiment.num_threads);
  const EnvFacts& facts = collector.facts();
  torch::manual_seed(config.experiment.seed);
  std::unique_ptr<Algorithm> algorithm = BuildAlgorithm(config, tasks, facts);
  BatchedExecutor& exec = collector.executor();
  const int64_t n = collector.num_envs();
  const int64_t rounds = algorithm->rounds_per_iteration();
  const int64_t steps = rounds * facts.episode_length;

  // random env actions within the action space (Box bounds or Discrete indices)
  std::mt19937_64 rng(config.experiment.seed);
  std::vector<float> actions(static_cast<size_t>(n * facts.action_dim));
  std::vector<float> unit(actions.size());

  CollectionBenchResult result;
  result.num_envs = n;
  result.num_threads = config.experiment.num_threads;
  result.steps_per_repeat = steps * n;
  std::vector<double> ratios;
  int64_t round = 0;
  for (int r = 0; r < repeats + 1; ++r) {  // repeat 0 warms up both arms
    double env_s = 0.0;
    for (int64_t k = 0; k < rounds; ++k) {
      collector.BeginRound(config.experiment.seed, round++);
      for (int64_t s = 0; s < facts.episode_length; ++s) {
        std::uniform_real_distribution<float> u(-1.0f, 1.0f);
        for (float& a : unit) {
          a = facts.num_actions > 0 ? static_cast<float>(rng() % facts.num_actions) : u(rng);
        }
        PolicyToEnvActions(unit.data(), n, facts, actions.data());
        const auto t0 = std::chrono::steady_clock::now();
        exec.Step(actions);
        env_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      }
    }
    const nlohmann::json row = algorithm->TrainIteration(collector, round, 0);
    round += rounds;
    const double collect_s =
        row.at("time_act_s").get<double>() + row.at("time_env_s").get<double>();
    if (r == 0) continue;
    const double env_rate = static_cast<double>(steps * n) / env_s;
    const double collect_rate = static_cast<double>(steps * n) / collect_s;
    result.env_steps_per_s.push_back(env_rate);
    result.collection_steps_per_s.push_back(collect_rate);
    ratios.push_back(collect_rate / env_rate);
  }
  result.env_median = Median(result.env_steps_per_s);
  result.collection_median = Median(result.collection_steps_per_s);
  result.ratio = Median(ratios);
  return result;
}

}  // namespace manyworlds::experiments
