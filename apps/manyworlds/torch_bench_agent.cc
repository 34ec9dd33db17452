// manyworlds bench agent --algo NAME: one algorithm's update on random data
// of the given sizes, timed by the function its registry row names
// (experiments/agent_bench.h): SAC updates per second, on-policy
// optimisation throughput (PPO: one epoch; TRPO, TE-PPO: one whole update),
// RL2's and MAML's update on random trials, PEARL's update on per-task
// batches; with the thread configuration used.
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "apps/manyworlds/cli_util.h"
#include "apps/manyworlds/commands.h"
#include "manyworlds/agents/sac/sac_config.h"
#include "manyworlds/core/error.h"
#include "manyworlds/core/limits.h"
#include "manyworlds/experiments/agent_bench.h"
#include "manyworlds/experiments/algorithms.h"
#include "manyworlds/experiments/trainer.h"
#include "manyworlds/nn/device.h"

namespace manyworlds::cli {
namespace {

struct BenchAgentArgs {
  std::string agent = "sac";
  std::string device = "cpu";
  experiments::AgentBenchSizes sizes;
  bool json = false;
};

std::string Join(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

void RunBenchAgent(const BenchAgentArgs& args) {
  const experiments::AlgorithmInfo* info = experiments::LookupAlgorithm(args.agent);
  if (info == nullptr) throw ConfigError(experiments::UnknownAlgorithm("--algo", args.agent));
  nn::ResolveDevice(args.device, "--device");  // "cpu", or why not a GPU
  const experiments::AgentBenchResult result = info->bench(info->name, args.sizes);
  if (args.json) {
    PrintJson(result.json);
  } else {
    std::cout << result.summary;
  }
}

}  // namespace

void AddBenchAgentSubcommand(CLI::App& bench, CommandContext&) {
  auto args = std::make_shared<BenchAgentArgs>();
  CLI::App* cmd = bench.add_subcommand(
      "agent",
      "Agent updates per second: full SAC updates (critic, actor, temperature, targets) on\n"
      "random batches of the given sizes; the observation carries no task id, the\n"
      "learner conditions on the task index per --architecture");
  cmd->add_option("--algo,--agent", args->agent,
                  "algorithm to time: " + experiments::AlgorithmNames())
      ->capture_default_str();
  cmd->add_option("--device", args->device,
                  std::string("where the learner runs: ") + nn::kDeviceValues +
                      " (the learners run on the CPU in this version)")
      ->capture_default_str();
  cmd->add_option("--trial-length", args->sizes.trial_length,
                  "rl2, maml: steps per trial (maml: half before, half after adaptation)")
      ->capture_default_str()
      ->check(AtLeastOne(100000));
  cmd->add_option("--frame", args->sizes.frame,
                  "sac_ae: frames of FRAME x FRAME pixels (MTEnv's: 84)")
      ->capture_default_str()
      ->check(AtLeastOne(1024));
  cmd->add_option("--channels", args->sizes.channels,
                  "sac_ae: channels of a frame (9: three stacked RGB frames)")
      ->capture_default_str()
      ->check(AtLeastOne(64));
  cmd->add_option("--batch", args->sizes.batch,
                  "batch size (ppo/trpo: samples in the rollout; rl2/maml: trials; pearl: RL "
                  "transitions per task; distral: rows per task agent)")
      ->capture_default_str()
      ->check(AtLeastOne(1000000));
  cmd->add_option("--minibatch", args->sizes.minibatch,
                  "ppo: minibatch size of the epoch; trpo: of the value fit; rl2: trials; pearl: "
                  "context transitions per task")
      ->capture_default_str()
      ->check(AtLeastOne(1000000));
  cmd->add_option("--hidden", args->sizes.hidden, "hidden width of actor and critics")
      ->capture_default_str()
      ->check(AtLeastOne(16384));
  cmd->add_option("--layers", args->sizes.layers, "hidden layers of actor and critics")
      ->capture_default_str()
      ->check(AtLeastOne(64));
  cmd->add_option("--obs-dim", args->sizes.obs_dim, "observation size (without any task id)")
      ->capture_default_str()
      ->check(AtLeastOne(100000));
  cmd->add_option("--action-dim", args->sizes.action_dim, "action size")
      ->capture_default_str()
      ->check(AtLeastOne(4096));
  cmd->add_option("--tasks", args->sizes.tasks,
                  "number of tasks (batches draw task indices uniformly; pearl: the meta-batch)")
      ->capture_default_str()
      ->check(AtLeastOne(10000));
  cmd->add_option("--architecture", args->sizes.architecture,
                  "task conditioning: " + Join(agents::SacArchitectures()))
      ->capture_default_str();
  cmd->add_flag("--pcgrad", args->sizes.pcgrad,
                "combine per-task gradients with PCGrad (one backward per task in the batch)");
  cmd->add_flag("--gradnorm", args->sizes.gradnorm,
                "sac: learn per-task loss weights with GradNorm (one last-layer gradient per task)");
  cmd->add_flag("--disentangled-alpha", args->sizes.disentangled_alpha, "one temperature per task");
  cmd->add_option("--updates", args->sizes.updates,
                  "timed updates per repeat (after 3 warm-up updates)")
      ->capture_default_str()
      ->check(AtLeastOne(1000000));
  cmd->add_option("--repeats", args->sizes.repeats, "timed repeats (the median is reported)")
      ->capture_default_str()
      ->check(AtLeastOne(10000));
  cmd->add_option("--shards", args->sizes.shards,
                  "data-parallel shards of each update (SacConfig update_shards)")
      ->capture_default_str()
      ->check(AtLeastOne(kMaxThreads));
  cmd->add_option("--update-threads", args->sizes.update_threads,
                  "threads running the shards (0: one per shard, at most one per core)")
      ->capture_default_str()
      ->check(Unsigned());
  cmd->add_option("--torch-threads", args->sizes.torch_threads,
                  "libtorch intra-op threads (default: 1, as every learner sets)")
      ->check(AtLeastOne(kMaxThreads));
  cmd->add_option("--blas-threads", args->sizes.blas_threads,
                  "OpenBLAS threads (default: OPENBLAS_NUM_THREADS, else one per core); at most "
                  "one of --torch-threads and --blas-threads may be > 1")
      ->check(AtLeastOne(kMaxThreads));
  cmd->add_option("--seed", args->sizes.seed, "seed of the networks and the random batches")
      ->capture_default_str()
      ->check(Unsigned());
  cmd->add_flag("--json", args->json,
                "print JSON: updates_per_s (median), samples, ms_per_update, the configuration "
                "and the threads used");
  cmd->callback([args] {
    experiments::NameMemorySettingsOnFailure([&] { RunBenchAgent(*args); });
  });
}

}  // namespace manyworlds::cli
