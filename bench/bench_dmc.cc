// DeepMind-Control-style state steps against the raw MuJoCo cost of the same model (#35).
//
//   BM_EnvStep/<task>     DmcEnv::Step through the view overload (caller-owned buffers): action
//                         validation and clipping, ctrl written, the control step's physics
//                         with the warning check, observation, reward and info
//   BM_RawPhysics/<task>  the same compiled model and the same actions driven by hand: ctrl
//                         written, the control step's physics as the env calls it (legacy
//                         stepping: mj_step2, n_sub_steps - 1 mj_step, mj_step1, i.e.
//                         n_sub_steps physics steps with positions, velocities and sensors
//                         recomputed for the new state), then the quantities the observation
//                         and reward read summed (finger: its 13 sensor values; cheetah: qpos,
//                         qvel, the subtree velocity; walker: 7 body rotations' xx and xz,
//                         torso height and zz, qvel, the subtree velocity): the minimum an env
//                         must pay; before timing, one control step by hand must land
//                         bit for bit where the env's Step does, or the benchmark is skipped
// Both start every episode (1000 control steps) from the same initial state: the env's own
// Reset, and for the raw loop a copy of the state that a second env seeded alike reset to, so
// the two loops simulate the same trajectories and the ratio BM_RawPhysics / BM_EnvStep rate
// is what the env adds on top of the physics. Resets are not timed in either (the cheetah's
// settles for 200 physics steps, dm_control's initial state, not a step cost); BM_EnvReset/<task>
// times them alone. Counter: control steps/s (items_per_second; resets/s for BM_EnvReset).
//
//   build/bench/bench_dmc --benchmark_repetitions=5 --benchmark_min_time=0.3
//       --benchmark_enable_random_interleaving=true --benchmark_report_aggregates_only=true
//   (one command line)

#include <memory>
#include <span>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <mujoco/mujoco.h>

#include "manyworlds/core/rng.h"
#include "manyworlds/dmc/dmc_env.h"
#include "manyworlds/sim/model.h"

namespace manyworlds::dmc {
namespace {

constexpr int kActionBlock = 4096;  // pre-drawn actions, cycled

struct TaskCase {
  const char* name;
  DmcTask task;
  int action_size;
  int substeps;  // physics steps per control step (dmc_env.h)
};

constexpr TaskCase kCases[] = {{"finger-spin", DmcTask::kFingerSpin, 2, 2},
                               {"cheetah-run", DmcTask::kCheetahRun, 6, 1},
                               {"walker-walk", DmcTask::kWalkerWalk, 6, 10}};

std::vector<float> RandomActions(int action_size, uint64_t seed) {
  Rng rng(seed);
  std::vector<float> actions(static_cast<size_t>(action_size) * kActionBlock);
  for (float& a : actions) a = static_cast<float>(rng.Uniform(-1.0, 1.0));
  return actions;
}

std::unique_ptr<DmcEnv> MakeEnv(DmcTask task) {
  auto env = std::make_unique<DmcEnv>(DmcEnv::Config{.task = task});
  env->Seed(0);
  env->SeedTask(0);
  env->ResetTaskState();
  return env;
}

// The sum of what the task's observation and reward read (dmc_env.cc's WriteObs and
// RewardAndInfo).
double ReadQuantities(DmcTask task, const mjModel* m, const mjData* d) {
  double sum = 0;
  switch (task) {
    case DmcTask::kFingerSpin:
      for (int i = 0; i < m->nsensordata; ++i) sum += d->sensordata[i];
      break;
    case DmcTask::kCheetahRun:
      for (int i = 1; i < m->nq; ++i) sum += d->qpos[i];
      for (int i = 0; i < m->nv; ++i) sum += d->qvel[i];
      sum += d->sensordata[0];
      break;
    case DmcTask::kWalkerWalk:
      for (int b = 1; b <= 7; ++b) sum += d->xmat[9 * b] + d->xmat[9 * b + 2];
      sum += d->xpos[5] + d->xmat[17];
      for (int i = 0; i < m->nv; ++i) sum += d->qvel[i];
      sum += d->sensordata[0];
      break;
  }
  return sum;
}

void BM_EnvStep(benchmark::State& bench, const TaskCase& c) {
  std::unique_ptr<DmcEnv> env = MakeEnv(c.task);
  const EnvSpec& spec = env->spec();
  std::vector<float> env_obs(spec.env_obs_space.flat_size());
  std::vector<float> task_obs(spec.task_obs_space.flat_size());
  std::vector<float> info(spec.info_fields.size());
  float reward = 0.0f;
  bool terminated = false, truncated = false;
  const StepView view{env_obs, task_obs, &reward, &terminated, &truncated, info, {}};
  env->Reset(ObsView{env_obs, task_obs, {}});
  const std::vector<float> actions = RandomActions(c.action_size, 1);
  int t = 0;
  for (auto _ : bench) {
    const float* a = actions.data() + c.action_size * (t++ % kActionBlock);
    env->Step(std::span<const float>(a, c.action_size), view);
    benchmark::DoNotOptimize(reward);
    if (terminated || truncated) {
      bench.PauseTiming();
      env->Reset(ObsView{env_obs, task_obs, {}});
      bench.ResumeTiming();
    }
  }
  bench.SetItemsProcessed(bench.iterations());
}

void BM_RawPhysics(benchmark::State& bench, const TaskCase& c) {
  // A second env seeded alike only supplies each episode's initial state.
  std::unique_ptr<DmcEnv> starts = MakeEnv(c.task);
  starts->Reset();
  sim::ModelPtr model(mj_copyModel(nullptr, starts->model()));
  sim::DataPtr data = sim::MakeData(model.get());
  mjModel* m = model.get();
  mjData* d = data.get();
  mj_copyData(d, m, starts->data());
  const int64_t episode = starts->spec().max_episode_steps;
  const std::vector<float> actions = RandomActions(c.action_size, 1);
  {
    // One control step by hand must land exactly where the env's Step does.
    std::unique_ptr<DmcEnv> check = MakeEnv(c.task);
    check->Reset();
    check->Step(std::span<const float>(actions.data(), c.action_size));
    for (int i = 0; i < m->nu; ++i) d->ctrl[i] = actions[i];
    mj_step2(m, d);
    for (int i = 1; i < c.substeps; ++i) mj_step(m, d);
    mj_step1(m, d);
    const mjData* e = check->data();
    bool same = true;
    for (int i = 0; i < m->nq; ++i) same = same && d->qpos[i] == e->qpos[i];
    for (int i = 0; i < m->nv; ++i) same = same && d->qvel[i] == e->qvel[i];
    if (!same) bench.SkipWithError("a control step by hand differs from the env's Step");
    mj_copyData(d, m, starts->data());
  }
  int t = 0;
  int64_t in_episode = 0;
  for (auto _ : bench) {
    const float* a = actions.data() + c.action_size * (t++ % kActionBlock);
    for (int i = 0; i < m->nu; ++i) d->ctrl[i] = a[i];
    mj_step2(m, d);
    for (int i = 1; i < c.substeps; ++i) mj_step(m, d);
    mj_step1(m, d);
    benchmark::DoNotOptimize(ReadQuantities(c.task, m, d));
    if (++in_episode == episode) {
      bench.PauseTiming();
      starts->Reset();
      mj_copyData(d, m, starts->data());
      in_episode = 0;
      bench.ResumeTiming();
    }
  }
  bench.SetItemsProcessed(bench.iterations());
}

// Reset alone (not a step cost, so left out of the two above): a new initial state drawn as
// dm_control draws it, the cheetah's 200 settling physics steps included.
void BM_EnvReset(benchmark::State& bench, const TaskCase& c) {
  std::unique_ptr<DmcEnv> env = MakeEnv(c.task);
  const EnvSpec& spec = env->spec();
  std::vector<float> env_obs(spec.env_obs_space.flat_size());
  std::vector<float> task_obs(spec.task_obs_space.flat_size());
  for (auto _ : bench) {
    env->Reset(ObsView{env_obs, task_obs, {}});
    benchmark::DoNotOptimize(env_obs.data());
  }
  bench.SetItemsProcessed(bench.iterations());
}

int RegisterAll() {
  for (const TaskCase& c : kCases) {
    benchmark::RegisterBenchmark((std::string("BM_EnvStep/") + c.name).c_str(), BM_EnvStep, c)
        ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark((std::string("BM_RawPhysics/") + c.name).c_str(), BM_RawPhysics, c)
        ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark((std::string("BM_EnvReset/") + c.name).c_str(), BM_EnvReset, c)
        ->Unit(benchmark::kMicrosecond);
  }
  return 0;
}
const int registered = RegisterAll();

}  // namespace
}  // namespace manyworlds::dmc

BENCHMARK_MAIN();
