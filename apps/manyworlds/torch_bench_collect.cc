// manyworlds bench collect CONFIG [key=value ...]: a training config's
// collection throughput (policy forward, action mapping, episode
// bookkeeping, buffer writes, env steps) against the raw executor on the
// same envs and threads, interleaved (experiments/loops/collection_bench.h).
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "apps/manyworlds/cli_util.h"
#include "apps/manyworlds/commands.h"
#include "manyworlds/core/error.h"
#include "manyworlds/experiments/loops/collection_bench.h"
#include "manyworlds/experiments/train_config.h"
#include "manyworlds/experiments/trainer.h"

namespace manyworlds::cli {
namespace {

struct BenchCollectArgs {
  std::vector<std::string> positional;  // CONFIG [key=value ...]
  int repeats = 5;
  bool json = false;
};

void RunBenchCollect(const BenchCollectArgs& args) {
  if (args.positional.empty()) {
    throw ConfigError("bench collect: give a config file (e.g. configs/mt10_mtppo.yaml)");
  }
  const std::vector<std::string> overrides(args.positional.begin() + 1, args.positional.end());
  const experiments::TrainConfig config =
      experiments::TrainConfig::Load(args.positional.front(), overrides);
  const experiments::CollectionBenchResult r =
      experiments::MeasureCollection(config, args.repeats);
  if (args.json) {
    PrintJson({{"config", args.positional.front()},
               {"algo", config.agent.algo()},
               {"env", config.env.id},
               {"num_envs", r.num_envs},
               {"num_threads", r.num_threads},
               {"steps_per_repeat", r.steps_per_repeat},
               {"env_steps_per_s", r.env_median},
               {"collection_steps_per_s", r.collection_median},
               {"ratio", r.ratio},
               {"env_samples", r.env_steps_per_s},
               {"collection_samples", r.collection_steps_per_s}});
    return;
  }
  std::cout << config.agent.algo() << " on " << config.env.id << " (" << r.num_envs << " envs, "
            << r.num_threads << " thread" << (r.num_threads == 1 ? "" : "s")
            << "): collection " << Human(r.collection_median) << " env steps/s, executor alone "
            << Human(r.env_median) << " env steps/s, ratio " << Fixed(r.ratio, 3)
            << " (medians of " << r.env_steps_per_s.size() << " interleaved repeats of "
            << r.steps_per_repeat << " steps)\n";
}

}  // namespace

void AddBenchCollectSubcommand(CLI::App& bench, CommandContext&) {
  auto args = std::make_shared<BenchCollectArgs>();
  CLI::App* cmd = bench.add_subcommand(
      "collect",
      "Collection env steps/s of a training config (policy forward for all envs in one\n"
      "batched call, action mapping, bookkeeping, buffer writes) against the executor\n"
      "stepping the same envs on the same threads with random actions, interleaved");
  cmd->add_option("args", args->positional,
                  "CONFIG [key=value ...]: a training config and overrides (as `train`)")
      ->required();
  cmd->add_option("--repeats", args->repeats,
                  "timed iterations of each arm after one warm-up (medians reported)")
      ->capture_default_str()
      ->check(AtLeastOne());
  cmd->add_flag("--json", args->json, "print JSON (medians, the per-repeat samples, ratio)");
  cmd->callback([args] {
    experiments::NameMemorySettingsOnFailure([&] { RunBenchCollect(*args); });
  });
}

}  // namespace manyworlds::cli
