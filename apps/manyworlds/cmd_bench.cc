// manyworlds bench env --env ID: batched stepping throughput (MeasureThroughput).
#include <iostream>

#include "apps/manyworlds/cli_util.h"
#include "apps/manyworlds/commands.h"
#include "manyworlds/core/limits.h"
#include "manyworlds/core/throughput.h"
#include "manyworlds/envs/all.h"

namespace manyworlds::cli {
namespace {

struct BenchEnvArgs {
  std::string env;
  std::vector<std::string> options;
  ThroughputOptions throughput{.num_envs = 16, .num_threads = 1, .steps = 200000, .repeats = 5,
                               .seed = 0};
  bool json = false;
};

void RunBenchEnv(const BenchEnvArgs& args) {
  const nlohmann::json options = ParseEnvOptions(args.options);
  // a bad id or option fails here, before any timing
  if (const std::string note = PixelObservationNote(*Make(args.env, options)); !note.empty()) {
    std::cerr << args.env << ": " << note << "\n";
  }
  const ThroughputResult r =
      MeasureThroughput([&](int) { return Make(args.env, options); }, args.throughput);
  if (args.json) {
    PrintJson({{"env", args.env},
               {"num_envs", r.num_envs},
               {"num_threads", r.num_threads},
               {"steps_per_repeat", r.steps_per_repeat},
               {"repeats", r.samples.size()},
               {"steps_per_s", r.steps_per_s},
               {"samples", r.samples},
               {"ns_per_step", r.ns_per_step}});
    return;
  }
  std::cout << args.env << ": " << Human(r.steps_per_s) << " env steps/s (median of "
            << r.samples.size() << " repeats of " << r.steps_per_repeat << " steps; "
            << r.num_envs << " envs, " << r.num_threads << " thread"
            << (r.num_threads == 1 ? "" : "s") << ", " << Fixed(r.ns_per_step, 1)
            << " ns/step)\nsamples:";
  for (double s : r.samples) std::cout << " " << Human(s);
  std::cout << "\n";
}

}  // namespace

void AddBenchCommand(CLI::App& app, CommandContext& context) {
  (void)context;
  CLI::App* bench = app.add_subcommand("bench", "Benchmarks");
  bench->require_subcommand(1);
  auto args = std::make_shared<BenchEnvArgs>();
  CLI::App* cmd = bench->add_subcommand("env", "Env steps per second through the batched executor");
  cmd->add_option("--env", args->env, "env id (see `manyworlds envs`)")->required();
  cmd->add_option("--num-envs", args->throughput.num_envs, "envs stepped together")
      ->capture_default_str()
      ->check(AtLeastOne(kMaxEnvs));
  cmd->add_option("--threads", args->throughput.num_threads, "worker threads")
      ->capture_default_str()
      ->check(AtLeastOne(kMaxThreads));
  cmd->add_option("--steps", args->throughput.steps, "env steps per repeat")
      ->capture_default_str()
      ->check(AtLeastOne());
  cmd->add_option("--repeats", args->throughput.repeats, "timed repeats (the median is reported)")
      ->capture_default_str()
      ->check(AtLeastOne());
  cmd->add_option("--seed", args->throughput.seed, "seed of envs, tasks and actions")
      ->capture_default_str()
      ->check(Unsigned());
  cmd->add_option("--option", args->options, "env option key=value (repeatable)");
  cmd->add_flag("--json", args->json, "print JSON (steps_per_s is the median)");
  cmd->callback([args] { RunBenchEnv(*args); });
#ifdef MANYWORLDS_HAS_AGENTS
  AddBenchAgentSubcommand(*bench, context);
  AddBenchCollectSubcommand(*bench, context);
#endif
}

}  // namespace manyworlds::cli
