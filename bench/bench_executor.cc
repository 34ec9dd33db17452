// BatchedExecutor benchmarks.
//
//   BM_DirectLoop/N        the same cheap env stepped by hand (no executor)
//   BM_ExecutorCheap/N     that env through the executor, 1 thread: the
//                          difference to BM_DirectLoop is the executor's cost
//   BM_ExecutorCartPole/N  a CartPole-like env, 1 thread (target >= 2M/s)
//   BM_ExecutorExpensive/T ~20 us of arithmetic per step, 8 envs, T threads
//   BM_ExecutorExpensiveAsync/T  the same through Send/Recv
// Counters: time_per_env_step and env steps/s (items_per_second).

#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include <benchmark/benchmark.h>

#include "manyworlds/core/env.h"
#include "manyworlds/core/executor.h"
#include "manyworlds/core/rng.h"

namespace manyworlds {
namespace {

// Minimal env: the executor's and Env's bookkeeping dominate.
class CheapEnv : public Env {
 public:
  CheapEnv() : Env(MakeSpec()) {}

  static EnvSpec MakeSpec() {
    EnvSpec spec;
    spec.id = "bench-cheap";
    spec.action_space = Space::Box(-1.0f, 1.0f, {1});
    spec.env_obs_space = Space::Box(-10.0f, 10.0f, {4});
    spec.task_obs_space = Space::Box(0.0f, 1.0f, {1});
    spec.info_fields = {"success"};
    spec.max_episode_steps = 200;
    return spec;
  }

 protected:
  TaskState DoSampleTaskState(Rng&) override { return TaskState{id(), nlohmann::json::object()}; }
  TaskState DoGetTaskState() const override { return TaskState{id(), nlohmann::json::object()}; }
  void DoSetTaskState(const TaskState&) override {
    const float obs[1] = {0.5f};
    SetTaskObs(obs);
  }
  void DoReset(const ObsView& out) override {
    x_ = 0.0f;
    for (float& v : out.env_obs) v = 0.0f;
  }
  void DoStep(std::span<const float> action, const StepView& out) override {
    x_ += action[0];
    out.env_obs[0] = x_;
    *out.reward = -x_ * x_;
  }

 private:
  float x_ = 0.0f;
};

// CartPole dynamics (Barto, Sutton & Anderson 1983; Euler, tau 0.02).
class CartPoleLikeEnv : public Env {
 public:
  CartPoleLikeEnv() : Env(MakeSpec()) {}

  static EnvSpec MakeSpec() {
    const float inf = std::numeric_limits<float>::infinity();
    EnvSpec spec;
    spec.id = "bench-cartpole";
    spec.action_space = Space::Discrete(2);
    spec.env_obs_space = Space::Box(-inf, inf, {4});
    spec.task_obs_space = Space::Box(0.0f, 10.0f, {1});
    spec.max_episode_steps = 500;
    return spec;
  }

 protected:
  TaskState DoSampleTaskState(Rng&) override { return TaskState{id(), {{"force", 10.0}}}; }
  TaskState DoGetTaskState() const override { return TaskState{id(), {{"force", 10.0}}}; }
  void DoSetTaskState(const TaskState&) override {
    const float obs[1] = {10.0f};
    SetTaskObs(obs);
  }
  void DoReset(const ObsView& out) override {
    for (int k = 0; k < 4; ++k) {
      s_[k] = env_rng().Uniform(-0.05, 0.05);
      out.env_obs[k] = static_cast<float>(s_[k]);
    }
  }
  void DoStep(std::span<const float> action, const StepView& out) override {
    constexpr double kGravity = 9.8, kMassCart = 1.0, kMassPole = 0.1, kLength = 0.5;
    constexpr double kTotal = kMassCart + kMassPole, kPoleMassLength = kMassPole * kLength;
    constexpr double kTau = 0.02;
    const double force = action[0] > 0.5f ? 10.0 : -10.0;
    const double cos_t = std::cos(s_[2]), sin_t = std::sin(s_[2]);
    const double temp = (force + kPoleMassLength * s_[3] * s_[3] * sin_t) / kTotal;
    const double theta_acc = (kGravity * sin_t - cos_t * temp) /
                             (kLength * (4.0 / 3.0 - kMassPole * cos_t * cos_t / kTotal));
    const double x_acc = temp - kPoleMassLength * theta_acc * cos_t / kTotal;
    s_[0] += kTau * s_[1];
    s_[1] += kTau * x_acc;
    s_[2] += kTau * s_[3];
    s_[3] += kTau * theta_acc;
    for (int k = 0; k < 4; ++k) out.env_obs[k] = static_cast<float>(s_[k]);
    *out.terminated = std::abs(s_[0]) > 2.4 || std::abs(s_[2]) > 0.2095;
    *out.reward = 1.0f;
  }

 private:
  double s_[4] = {};
};

// Fixed arithmetic work, calibrated once to about 20 us on this machine, so
// that adding threads shows real scaling (a clock-based wait would "scale"
// even on a single busy core).
uint64_t BusyWork(uint64_t iterations, uint64_t x) {
  for (uint64_t i = 0; i < iterations; ++i) {
    x = x * 6364136223846793005ull + 1442695040888963407ull;
    x ^= x >> 29;
  }
  return x;
}

uint64_t IterationsFor20us() {
  static const uint64_t iterations = [] {
    constexpr uint64_t kProbe = 2'000'000;
    double best = std::numeric_limits<double>::infinity();
    for (int r = 0; r < 5; ++r) {
      const auto start = std::chrono::steady_clock::now();
      benchmark::DoNotOptimize(BusyWork(kProbe, r));
      const std::chrono::duration<double> d = std::chrono::steady_clock::now() - start;
      best = std::min(best, d.count());
    }
    return static_cast<uint64_t>(kProbe * 20e-6 / best);
  }();
  return iterations;
}

class ExpensiveEnv : public CheapEnv {
 protected:
  void DoStep(std::span<const float> action, const StepView& out) override {
    state_ = BusyWork(IterationsFor20us(), state_);
    CheapEnv::DoStep(action, out);
    out.info[0] = static_cast<float>(state_ & 1);
  }

 private:
  uint64_t state_ = 1;
};

template <typename E>
std::vector<std::unique_ptr<Env>> MakeEnvs(int n) {
  std::vector<std::unique_ptr<Env>> envs;
  for (int i = 0; i < n; ++i) envs.push_back(std::make_unique<E>());
  return envs;
}

// A few pre-sampled action batches, cycled.
std::vector<std::vector<float>> ActionPool(BatchedExecutor& exec) {
  Rng rng(7);
  std::vector<std::vector<float>> pool(8, std::vector<float>(exec.num_envs() * exec.action_size()));
  for (auto& batch : pool) {
    for (int i = 0; i < exec.num_envs(); ++i) {
      exec.env(i).spec().action_space.Sample(
          rng, std::span<float>(batch.data() + i * exec.action_size(), exec.action_size()));
    }
  }
  return pool;
}

void SetCounters(benchmark::State& state, int num_envs) {
  const double steps = static_cast<double>(state.iterations()) * num_envs;
  state.SetItemsProcessed(static_cast<int64_t>(steps));
  // Shown as a time (e.g. "15.2n" = 15.2 ns) per env step.
  state.counters["time_per_env_step"] =
      benchmark::Counter(steps, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

template <typename E>
void RunExecutor(benchmark::State& state, int num_envs, int num_threads, bool async) {
  BatchedExecutor exec(MakeEnvs<E>(num_envs), {.num_threads = num_threads});
  exec.Seed(1, 2);
  exec.Reset();
  const auto pool = ActionPool(exec);
  size_t k = 0;
  for (auto _ : state) {
    const std::vector<float>& actions = pool[k++ % pool.size()];
    if (async) {
      exec.Send(actions);
      exec.Recv();
    } else {
      exec.Step(actions);
    }
    benchmark::DoNotOptimize(exec.rewards().data());
  }
  SetCounters(state, num_envs);
}

void BM_DirectLoop(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  auto envs = MakeEnvs<CheapEnv>(n);
  std::vector<float> obs(n * 4), task_obs(n), rewards(n), info(n);
  std::unique_ptr<bool[]> terminated(new bool[n]), truncated(new bool[n]);
  for (int i = 0; i < n; ++i) envs[i]->Reset(ObsView{{&obs[4 * i], 4}, {&task_obs[i], 1}, {}});
  std::vector<float> actions(n, 0.25f);
  for (auto _ : state) {
    for (int i = 0; i < n; ++i) {
      envs[i]->Step({&actions[i], 1}, StepView{{&obs[4 * i], 4},
                                               {&task_obs[i], 1},
                                               &rewards[i],
                                               &terminated[i],
                                               &truncated[i],
                                               {&info[i], 1},
                                               {}});
      if (terminated[i] || truncated[i]) {
        envs[i]->Reset(ObsView{{&obs[4 * i], 4}, {&task_obs[i], 1}, {}});
      }
    }
    benchmark::DoNotOptimize(rewards.data());
  }
  SetCounters(state, n);
}

void BM_ExecutorCheap(benchmark::State& state) {
  RunExecutor<CheapEnv>(state, static_cast<int>(state.range(0)), 1, false);
}

void BM_ExecutorCartPole(benchmark::State& state) {
  RunExecutor<CartPoleLikeEnv>(state, static_cast<int>(state.range(0)), 1, false);
}

void BM_ExecutorExpensive(benchmark::State& state) {
  RunExecutor<ExpensiveEnv>(state, 8, static_cast<int>(state.range(0)), false);
}

void BM_ExecutorExpensiveAsync(benchmark::State& state) {
  RunExecutor<ExpensiveEnv>(state, 8, static_cast<int>(state.range(0)), true);
}

constexpr int kRepetitions = 5;

BENCHMARK(BM_DirectLoop)
    ->Arg(1)
    ->Arg(16)
    ->Arg(256)
    ->Repetitions(kRepetitions)
    ->ReportAggregatesOnly(true);
BENCHMARK(BM_ExecutorCheap)
    ->Arg(1)
    ->Arg(16)
    ->Arg(256)
    ->Arg(4096)
    ->Repetitions(kRepetitions)
    ->ReportAggregatesOnly(true);
BENCHMARK(BM_ExecutorCartPole)
    ->Arg(1)
    ->Arg(16)
    ->Arg(256)
    ->Repetitions(kRepetitions)
    ->ReportAggregatesOnly(true);
BENCHMARK(BM_ExecutorExpensive)
    ->Arg(1)
    ->Arg(2)
    ->Repetitions(kRepetitions)
    ->ReportAggregatesOnly(true)
    ->UseRealTime()
    ->MinTime(0.2);
BENCHMARK(BM_ExecutorExpensiveAsync)
    ->Arg(1)
    ->Arg(2)
    ->Repetitions(kRepetitions)
    ->ReportAggregatesOnly(true)
    ->UseRealTime()
    ->MinTime(0.2);

}  // namespace
}  // namespace manyworlds

BENCHMARK_MAIN();
