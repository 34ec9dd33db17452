// Box world: model building and step cost.
//
//   BM_BuildWorld/<boxes>   GenerateWorld + BuildWorldModel + MakeData for a
//                           new seed every iteration (what a reset on a new
//                           world structure costs, the MJCF text included)
//   BM_TenThousandWorlds    10,000 consecutive worlds set on one env
//                           (SetTaskState, each a new structure, then Reset):
//                           time per world and the process's resident memory
//                           after the first 100 worlds and after all 10,000
//                           (counters rss_after_100_MiB, rss_after_10000_MiB,
//                           rss_growth_KiB); a leak shows as growth
//   BM_EnvStep/<id>         BoxWorldEnv::Step through the Env API: clipping,
//                           ctrl scaling, 5 physics substeps with the warning
//                           check, the observation, reward, info
//   BM_RawPhysics/<id>      the same model and actions driven by hand: ctrl
//                           written, 5 mj_step calls, agent and box qpos read
// Both step benchmarks restart from the same state every 1024 steps.
//
//   build-box/bench/bench_boxworld --benchmark_repetitions=9
//     --benchmark_enable_random_interleaving=true --benchmark_report_aggregates_only=true
//   (one command line)

#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <mujoco/mujoco.h>

#include "manyworlds/boxworld/box_world_env.h"
#include "manyworlds/boxworld/world_model.h"
#include "manyworlds/core/rng.h"
#include "manyworlds/sim/model.h"

namespace manyworlds::boxworld {
namespace {

constexpr int kActionBlock = 4096;
constexpr int kEpisode = 1024;

double ResidentMiB() {
  std::ifstream statm("/proc/self/statm");
  long pages_total = 0, pages_resident = 0;
  statm >> pages_total >> pages_resident;
  return static_cast<double>(pages_resident) * sysconf(_SC_PAGESIZE) / (1024.0 * 1024.0);
}

WorldDistribution Distribution(int boxes) {
  WorldDistribution d;
  d.floor_size = {4.0, 8.0};
  d.num_boxes = {boxes, boxes};
  d.box_shapes = {Shape::kBox, Shape::kCylinder, Shape::kSphere};
  d.box_size = {0.1, 0.25};
  d.box_mass = {0.03, 0.3};
  d.random_colors = true;
  // room for the target next to 16 boxes
  d.success_radius_ratio = 0.1;
  d.min_target_distance_ratio = 0.1;
  return d;
}

void BM_BuildWorld(benchmark::State& bench) {
  const WorldDistribution d = Distribution(static_cast<int>(bench.range(0)));
  uint64_t seed = 0;
  for (auto _ : bench) {
    const WorldParams world = GenerateWorld(d, seed++);
    sim::ModelPtr model = BuildWorldModel(world);
    sim::DataPtr data = sim::MakeData(model.get());
    benchmark::DoNotOptimize(data.get());
  }
  bench.SetItemsProcessed(bench.iterations());
}
BENCHMARK(BM_BuildWorld)->Arg(1)->Arg(4)->Arg(16)->Unit(benchmark::kMillisecond);

void BM_TenThousandWorlds(benchmark::State& bench) {
  BoxWorldEnv::Config config;
  config.task = BoxTask::kComplex;
  config.distribution = Distribution(4);
  config.distribution.num_boxes = {1, 8};
  for (auto _ : bench) {
    BoxWorldEnv env(config);
    env.SeedTask(0);
    double after_100 = 0;
    for (int i = 0; i < 10000; ++i) {
      env.ResetTaskState();
      env.Reset();
      if (i == 99) after_100 = ResidentMiB();
    }
    const double after_all = ResidentMiB();
    bench.counters["rss_after_100_MiB"] = after_100;
    bench.counters["rss_after_10000_MiB"] = after_all;
    bench.counters["rss_growth_KiB"] = (after_all - after_100) * 1024;
    bench.counters["models_built"] = static_cast<double>(env.models_built());
    bench.counters["ms_per_world"] = benchmark::Counter(
        10000, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  }
}
BENCHMARK(BM_TenThousandWorlds)->Iterations(1)->Unit(benchmark::kSecond);

std::vector<float> RandomActions(uint64_t seed) {
  Rng rng(seed);
  std::vector<float> actions(3 * kActionBlock);
  for (float& a : actions) a = static_cast<float>(rng.Uniform(-1.0, 1.0));
  return actions;
}

std::unique_ptr<BoxWorldEnv> MakeEnv(BoxTask task, int boxes) {
  BoxWorldEnv::Config config;
  config.task = task;
  config.distribution.num_boxes = {boxes, boxes};
  auto env = std::make_unique<BoxWorldEnv>(config);
  env->SeedTask(0);
  env->ResetTaskState();
  env->Reset();
  return env;
}

void BM_EnvStep(benchmark::State& bench, BoxTask task, int boxes) {
  std::unique_ptr<BoxWorldEnv> env = MakeEnv(task, boxes);
  // an episode that ends early (random actions reaching the target) restarts
  // too; `early_ends` counts them (a reset costs about one step)
  const std::vector<float> actions = RandomActions(1);
  int t = 0, in_episode = 0, early_ends = 0;
  for (auto _ : bench) {
    const float* a = actions.data() + 3 * (t++ % kActionBlock);
    StepResult step = env->Step(std::span<const float>(a, 3));
    benchmark::DoNotOptimize(step.reward);
    if (++in_episode == kEpisode || step.terminated || step.truncated) {
      early_ends += in_episode < kEpisode;
      env->Reset();
      in_episode = 0;
    }
  }
  bench.SetItemsProcessed(bench.iterations());
  bench.counters["early_ends"] = early_ends;
}

void BM_RawPhysics(benchmark::State& bench, BoxTask task, int boxes) {
  std::unique_ptr<BoxWorldEnv> env = MakeEnv(task, boxes);
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
    const float* a = actions.data() + 3 * (t++ % kActionBlock);
    for (int i = 0; i < m->nu; ++i) d->ctrl[i] = a[i] * m->actuator_ctrlrange[2 * i + 1];
    for (int i = 0; i < kFrameSkip; ++i) mj_step(m, d);
    double read = 0;
    for (int i = 0; i < m->nq; ++i) read += d->qpos[i];
    benchmark::DoNotOptimize(read);
    if (++in_episode == kEpisode) {
      mj_copyData(d, m, start.get());
      mj_forward(m, d);
      in_episode = 0;
    }
  }
  bench.SetItemsProcessed(bench.iterations());
}

BENCHMARK_CAPTURE(BM_EnvStep, simple_1box, BoxTask::kSimple, 1);
BENCHMARK_CAPTURE(BM_RawPhysics, simple_1box, BoxTask::kSimple, 1);
BENCHMARK_CAPTURE(BM_EnvStep, complex_4boxes, BoxTask::kComplex, 4);
BENCHMARK_CAPTURE(BM_RawPhysics, complex_4boxes, BoxTask::kComplex, 4);

}  // namespace
}  // namespace manyworlds::boxworld

BENCHMARK_MAIN();
