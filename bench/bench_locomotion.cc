// Half-cheetah step cost against the raw MuJoCo cost of the same model.
//
//   BM_EnvStep/<id>     HalfCheetahEnv::Step through the Env API: action
//                       validation and clipping, 5 physics substeps with the
//                       warning check, the 17 observations, forward velocity,
//                       reward and info
//   BM_RawPhysics/<id>  the same model and actions driven by hand: ctrl
//                       written, 5 mj_step calls, qpos and qvel read back
// Both restart from the same state every episode (200 steps), so the ratio
// is what the env adds on top of the physics. Counter: env steps/s.
//
//   build/bench/bench_locomotion --benchmark_repetitions=5 --benchmark_report_aggregates_only=true

#include <memory>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <mujoco/mujoco.h>

#include "manyworlds/core/rng.h"
#include "manyworlds/locomotion/half_cheetah.h"
#include "manyworlds/sim/model.h"

namespace manyworlds::locomotion {
namespace {

constexpr int kActionBlock = 4096;  // pre-drawn actions, cycled
constexpr int kEpisode = 200;

std::vector<float> RandomActions(uint64_t seed) {
  Rng rng(seed);
  std::vector<float> actions(6 * kActionBlock);
  for (float& a : actions) a = static_cast<float>(rng.Uniform(-1.0, 1.0));
  return actions;
}

std::unique_ptr<HalfCheetahEnv> MakeEnv(CheetahTask task) {
  auto env = std::make_unique<HalfCheetahEnv>(HalfCheetahEnv::Config{task, kEpisode, true, false});
  env->Seed(0);
  env->SeedTask(0);
  env->ResetTaskState();
  env->Reset();
  return env;
}

void BM_EnvStep(benchmark::State& bench, CheetahTask task) {
  std::unique_ptr<HalfCheetahEnv> env = MakeEnv(task);
  const std::vector<float> actions = RandomActions(1);
  int t = 0, in_episode = 0;
  for (auto _ : bench) {
    const float* a = actions.data() + 6 * (t++ % kActionBlock);
    StepResult step = env->Step(std::span<const float>(a, 6));
    benchmark::DoNotOptimize(step.reward);
    if (++in_episode == kEpisode) {
      env->Reset();
      in_episode = 0;
    }
  }
  bench.SetItemsProcessed(bench.iterations());
}

void BM_RawPhysics(benchmark::State& bench, CheetahTask task) {
  std::unique_ptr<HalfCheetahEnv> env = MakeEnv(task);
  sim::ModelPtr model(mj_copyModel(nullptr, env->model()));
  sim::DataPtr data = sim::MakeData(model.get());
  sim::DataPtr start = sim::MakeData(model.get());
  mj_copyData(start.get(), model.get(), env->data());
  mj_copyData(data.get(), model.get(), start.get());
  mjModel* m = model.get();
  mjData* d = data.get();
  const std::vector<float> actions = RandomActions(1);
  int t = 0, in_episode = 0;
  for (auto _ : bench) {
    const float* a = actions.data() + 6 * (t++ % kActionBlock);
    for (int i = 0; i < m->nu; ++i) d->ctrl[i] = a[i];
    for (int i = 0; i < 5; ++i) mj_step(m, d);
    double read = 0;
    for (int i = 0; i < m->nq; ++i) read += d->qpos[i];
    for (int i = 0; i < m->nv; ++i) read += d->qvel[i];
    benchmark::DoNotOptimize(read);
    if (++in_episode == kEpisode) {
      mj_copyData(d, m, start.get());
      mj_forward(m, d);
      in_episode = 0;
    }
  }
  bench.SetItemsProcessed(bench.iterations());
}

BENCHMARK_CAPTURE(BM_EnvStep, half_cheetah_vel, CheetahTask::kVelocity);
BENCHMARK_CAPTURE(BM_RawPhysics, half_cheetah_vel, CheetahTask::kVelocity);
BENCHMARK_CAPTURE(BM_EnvStep, half_cheetah_dir, CheetahTask::kDirection);
BENCHMARK_CAPTURE(BM_RawPhysics, half_cheetah_dir, CheetahTask::kDirection);

}  // namespace
}  // namespace manyworlds::locomotion

BENCHMARK_MAIN();
