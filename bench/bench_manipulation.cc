// Manipulation step cost against the raw MuJoCo cost of the same model.
//
//   BM_EnvStep/<task>     SawyerTask::Step through the Env API: action
//                         validation, mocap and gripper control, 5 physics
//                         substeps, observation, reward and info
//   BM_RawPhysics/<task>  the same model and the same actions, driven by
//                         hand: mocap and ctrl written, 5 mj_step calls, the
//                         hand, pad and object positions read back
// Both reset every 500 steps (the episode length) from the same settled
// state, so the ratio BM_EnvStep / BM_RawPhysics is what the env adds on top
// of the physics. Counter: env steps/s (items_per_second).
//
//   build/bench/bench_manipulation --benchmark_repetitions=5 --benchmark_report_aggregates_only=true

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <mujoco/mujoco.h>

#include "manyworlds/core/rng.h"
#include "manyworlds/manipulation/manipulation.h"
#include "manyworlds/manipulation/sawyer_task.h"
#include "manyworlds/sim/model.h"

namespace manyworlds::manipulation {
namespace {

constexpr int kActionBlock = 4096;  // pre-drawn actions, cycled

std::vector<float> RandomActions(uint64_t seed) {
  Rng rng(seed);
  std::vector<float> actions(4 * kActionBlock);
  for (float& a : actions) a = static_cast<float>(rng.Uniform(-1.0, 1.0));
  return actions;
}

void BM_EnvStep(benchmark::State& bench, const std::string& task_id) {
  std::unique_ptr<SawyerTask> env = MakeSawyerTask(task_id);
  env->Seed(0);
  env->SeedTask(0);
  env->ResetTaskState();
  env->Reset();
  const std::vector<float> actions = RandomActions(1);
  int t = 0;
  int in_episode = 0;
  for (auto _ : bench) {
    const float* a = actions.data() + 4 * (t++ % kActionBlock);
    StepResult step = env->Step(std::span<const float>(a, 4));
    benchmark::DoNotOptimize(step.reward);
    if (++in_episode == kMaxEpisodeSteps) {
      env->Reset();
      in_episode = 0;
    }
  }
  bench.SetItemsProcessed(bench.iterations());
}

void BM_RawPhysics(benchmark::State& bench, const std::string& task_id) {
  // The env is only used to build and settle the model in its first variation.
  std::unique_ptr<SawyerTask> env = MakeSawyerTask(task_id);
  env->Seed(0);
  env->SeedTask(0);
  env->ResetTaskState();
  env->Reset();
  sim::ModelPtr model(mj_copyModel(nullptr, env->model()));
  sim::DataPtr data = sim::MakeData(model.get());
  sim::DataPtr start = sim::MakeData(model.get());
  mj_copyData(start.get(), model.get(), env->data());
  mj_copyData(data.get(), model.get(), start.get());
  mjModel* m = model.get();
  mjData* d = data.get();

  const int mocap = m->body_mocapid[mj_name2id(m, mjOBJ_BODY, "hand_mocap")];
  const int hand_site = mj_name2id(m, mjOBJ_SITE, "hand_site");
  const int left_site = mj_name2id(m, mjOBJ_SITE, "left_pad_site");
  const int right_site = mj_name2id(m, mjOBJ_SITE, "right_pad_site");
  const int obj_body = std::max(0, mj_name2id(m, mjOBJ_BODY, "obj"));
  const SawyerTaskConfig& config = env->config();
  const std::vector<float> actions = RandomActions(1);
  int t = 0;
  int in_episode = 0;
  for (auto _ : bench) {
    const float* a = actions.data() + 4 * (t++ % kActionBlock);
    for (int i = 0; i < 3; ++i) {
      d->mocap_pos[3 * mocap + i] = std::clamp(d->mocap_pos[3 * mocap + i] + kActionScale * a[i],
                                               config.hand_low[i], config.hand_high[i]);
    }
    for (int i = 0; i < m->nu; ++i) d->ctrl[i] = a[3];
    for (int i = 0; i < kFrameSkip; ++i) mj_step(m, d);
    double read = 0;
    for (int i = 0; i < 3; ++i) {
      read += d->site_xpos[3 * hand_site + i] + d->site_xpos[3 * left_site + i] +
              d->site_xpos[3 * right_site + i] + d->xpos[3 * obj_body + i];
    }
    benchmark::DoNotOptimize(read);
    if (++in_episode == kMaxEpisodeSteps) {
      mj_copyData(d, m, start.get());
      mj_forward(m, d);
      in_episode = 0;
    }
  }
  bench.SetItemsProcessed(bench.iterations());
}

int RegisterAll() {
  for (const std::string& id : ManipulationTaskIds()) {
    benchmark::RegisterBenchmark(("BM_EnvStep/" + id).c_str(), BM_EnvStep, id);
    benchmark::RegisterBenchmark(("BM_RawPhysics/" + id).c_str(), BM_RawPhysics, id);
  }
  return 0;
}
const int registered = RegisterAll();

}  // namespace
}  // namespace manyworlds::manipulation

BENCHMARK_MAIN();
