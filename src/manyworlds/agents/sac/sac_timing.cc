#include "manyworlds/agents/sac/sac_timing.h"

#include <algorithm>
#include <chrono>
#include <string>
#include <vector>

#include "manyworlds/agents/sac/sac.h"
#include "manyworlds/core/error.h"
#include "manyworlds/core/median.h"

namespace manyworlds::agents {

SacTimingResult MeasureSacUpdates(const SacConfig& config, int obs_dim, int action_dim,
                                  int num_tasks, int updates, int repeats) {
  if (updates < 1) throw ConfigError("MeasureSacUpdates: updates must be >= 1");
  if (repeats < 1) throw ConfigError("MeasureSacUpdates: repeats must be >= 1");
  SacLearner sac(config, obs_dim, action_dim, num_tasks);
  at::Generator gen = at::detail::createCPUGenerator(config.seed + 1);
  const int64_t b = config.batch_size;
  // A few distinct batches, cycled, so that data generation is not timed.
  constexpr int kBatches = 4;
  std::vector<Batch> batches;
  for (int i = 0; i < kBatches; ++i) {
    Batch batch;
    batch.obs = torch::randn({b, obs_dim}, gen, torch::kFloat32);
    batch.action = torch::rand({b, action_dim}, gen, torch::kFloat32) * 2.0 - 1.0;
    batch.reward = torch::randn({b}, gen, torch::kFloat32);
    batch.next_obs = torch::randn({b, obs_dim}, gen, torch::kFloat32);
    batch.done = (torch::rand({b}, gen, torch::kFloat32) < 0.01).to(torch::kFloat32);
    // As the trainer's balanced replay batches when the batch divides into
    // the tasks (equally many rows per task, in random order; PaCo then
    // composes each task's parameters once), else uniform draws.
    batch.task_index =
        b % num_tasks == 0
            ? (torch::arange(b, torch::kInt64) % num_tasks).index_select(0, torch::randperm(b, gen))
            : torch::randint(num_tasks, {b}, gen, torch::kInt64);
    batches.push_back(std::move(batch));
  }
  constexpr int kWarmup = 3;
  for (int i = 0; i < kWarmup; ++i) sac.Update(batches[i % kBatches]);
  SacTimingResult result;
  result.update_threads = sac.update_threads();
  result.actor_params = sac.actor()->trunk()->num_params();
  result.critic_params = sac.critic()->online()->num_params();
  if (sac.task_encoder()) result.task_encoder_params = sac.task_encoder()->num_params();
  if (sac.encoder()) result.mixture_params = sac.encoder()->num_params();
  for (int r = 0; r < repeats; ++r) {
    const auto start = std::chrono::steady_clock::now();
    for (int i = 0; i < updates; ++i) sac.Update(batches[i % kBatches]);
    const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start;
    result.samples.push_back(updates / elapsed.count());
  }
  result.updates_per_s = Median(result.samples);
  return result;
}

double TimeSacUpdates(const SacConfig& config, int obs_dim, int action_dim, int num_tasks,
                      int updates) {
  return MeasureSacUpdates(config, obs_dim, action_dim, num_tasks, updates, 1).updates_per_s;
}

}  // namespace manyworlds::agents
