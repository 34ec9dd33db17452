#include "manyworlds/core/throughput.h"

#include <algorithm>
#include <chrono>
#include <span>
#include <string>

#include "manyworlds/core/error.h"
#include "manyworlds/core/executor.h"
#include "manyworlds/core/limits.h"
#include "manyworlds/core/median.h"
#include "manyworlds/core/memory.h"
#include "manyworlds/core/rng.h"

namespace manyworlds {
namespace {

// Distinct action batches cycled during timing: enough variety that envs do
// not settle into a fixed pattern, few enough to stay in cache.
constexpr int kActionPoolSize = 16;

}  // namespace

ThroughputResult MeasureThroughput(
    const std::function<std::unique_ptr<Env>(int env_index)>& make_env,
    const ThroughputOptions& opts) {
  if (opts.num_envs < 1 || opts.num_envs > kMaxEnvs) {
    throw ConfigError("MeasureThroughput: num_envs must be in [1, " + std::to_string(kMaxEnvs) +
                      "], got " + std::to_string(opts.num_envs));
  }
  if (opts.num_threads < 1 || opts.num_threads > kMaxThreads) {
    throw ConfigError("MeasureThroughput: num_threads must be in [1, " +
                      std::to_string(kMaxThreads) + "], got " + std::to_string(opts.num_threads));
  }
  if (opts.steps < 1) {
    throw ConfigError("MeasureThroughput: steps must be >= 1, got " + std::to_string(opts.steps));
  }
  if (opts.repeats < 1) {
    throw ConfigError("MeasureThroughput: repeats must be >= 1, got " +
                      std::to_string(opts.repeats));
  }
  if (!make_env) throw ConfigError("MeasureThroughput: make_env is empty");

  std::vector<std::unique_ptr<Env>> envs;
  envs.reserve(opts.num_envs);
  BatchMemoryCheck memory(opts.num_envs, std::to_string(opts.num_envs) + " envs", "--num-envs");
  for (int i = 0; i < opts.num_envs; ++i) {
    envs.push_back(make_env(i));
    if (!envs.back()) {
      throw ConfigError("MeasureThroughput: make_env(" + std::to_string(i) + ") returned null");
    }
    memory.Made(i);
  }
  BatchedExecutor exec(std::move(envs), {.num_threads = opts.num_threads});
  exec.Seed(MixSeed(opts.seed, 1), MixSeed(opts.seed, 2));
  exec.Reset();

  const int n = exec.num_envs();
  const size_t batch_size = static_cast<size_t>(n) * exec.action_size();
  std::vector<float> pool(batch_size * kActionPoolSize);
  Rng rng(MixSeed(opts.seed, 3));
  for (int b = 0; b < kActionPoolSize; ++b) {
    for (int i = 0; i < n; ++i) {
      const Space& space = exec.env(i).spec().action_space;
      space.Sample(rng, std::span<float>(pool.data() + b * batch_size + i * exec.action_size(),
                                         exec.action_size()));
    }
  }
  auto batch = [&](int64_t k) {
    return std::span<const float>(pool.data() + (k % kActionPoolSize) * batch_size, batch_size);
  };

  const int64_t batches = (opts.steps + n - 1) / n;
  // Warm-up: caches, branch predictors, workers out of their sleep.
  const int64_t warmup = std::max<int64_t>(1, batches / 10);
  int64_t k = 0;
  for (int64_t b = 0; b < warmup; ++b) exec.Step(batch(k++));

  ThroughputResult result;
  result.num_envs = n;
  result.num_threads = exec.num_threads();
  result.steps_per_repeat = batches * n;
  for (int r = 0; r < opts.repeats; ++r) {
    const auto start = std::chrono::steady_clock::now();
    for (int64_t b = 0; b < batches; ++b) exec.Step(batch(k++));
    const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start;
    result.samples.push_back(static_cast<double>(result.steps_per_repeat) /
                             std::max(elapsed.count(), 1e-12));
  }
  result.steps_per_s = Median(result.samples);
  result.min_steps_per_s = *std::min_element(result.samples.begin(), result.samples.end());
  result.max_steps_per_s = *std::max_element(result.samples.begin(), result.samples.end());
  result.ns_per_step = 1e9 / result.steps_per_s;
  return result;
}

}  // namespace manyworlds
