// manyworlds rollout --env ID: seeded episodes with a policy, per-episode
// table and summary (or RolloutSummary::ToJson with --json). A trained
// policy (--policy checkpoint:RUN_DIR) runs through RunCheckpointRollout.
#include <algorithm>
#include <iostream>
#include <memory>
#include <vector>

#include "apps/manyworlds/cli_util.h"
#include "apps/manyworlds/commands.h"
#include "manyworlds/core/error.h"
#include "manyworlds/core/limits.h"
#include "manyworlds/envs/all.h"

namespace manyworlds::cli {
namespace {

struct RolloutArgs {
  std::string env;
  std::string policy = "random";
  int episodes = 10;
  uint64_t seed = 0;
  uint64_t task_seed = 0;
  std::vector<std::string> options;
  int threads = 1;
  bool json = false;
};

// Benchmarks: --episodes variations of every task, in order, and a table of
// per-task success. Episode i of the flattened (task, variation) list is
// seeded as SeedEpisode says.
void RunGroupRollout(Env& env, const EnvMaker& make_env, const std::vector<TaskGroup>& groups,
                     const RolloutArgs& args) {
  std::vector<const TaskState*> states;
  std::vector<size_t> group_sizes;
  for (const TaskGroup& group : groups) {
    const size_t n = std::min(group.states.size(), static_cast<size_t>(args.episodes));
    for (size_t v = 0; v < n; ++v) states.push_back(&group.states[v]);
    group_sizes.push_back(n);
  }
  std::vector<EpisodeStats> stats =
      RunEpisodes(env, make_env, static_cast<int>(states.size()), args.threads,
                  [&](Env& e, int i) {
                    std::unique_ptr<Policy> policy =
                        SeedEpisode(e, args.policy, args.seed, args.task_seed, i);
                    e.SetTaskState(*states[static_cast<size_t>(i)]);
                    return policy;
                  });
  std::vector<GroupRollout> results;
  auto next = stats.begin();
  for (size_t g = 0; g < groups.size(); ++g) {
    std::vector<EpisodeStats> episodes(next, next + static_cast<std::ptrdiff_t>(group_sizes[g]));
    next += static_cast<std::ptrdiff_t>(group_sizes[g]);
    results.push_back({groups[g].name, Summarize(std::move(episodes))});
  }
  if (args.json) {
    PrintJson(GroupsToJson(results));
    return;
  }
  Table table({"task", ">episodes", ">mean return", ">success"});
  for (const GroupRollout& r : results) {
    table.AddRow({r.name, std::to_string(r.summary.episodes.size()),
                  Fixed(r.summary.mean_return, 1), SuccessRate(r.summary.success_rate)});
  }
  const RolloutSummary all = MergeGroups(results);
  table.AddRow({"mean", std::to_string(all.episodes.size()), Fixed(all.mean_return, 1),
                SuccessRate(all.success_rate)});
  table.Print(std::cout);
}

constexpr const char* kCheckpointPrefix = "checkpoint:";

void RunRollout(const RolloutArgs& args) {
  if (args.policy.rfind(kCheckpointPrefix, 0) == 0) {
#ifdef MANYWORLDS_HAS_AGENTS
    if (!args.options.empty()) {
      throw ConfigError("rollout: --option does not apply to a checkpoint policy (the run's "
                        "config fixes the env options)");
    }
    RunCheckpointRollout(args.policy.substr(std::string(kCheckpointPrefix).size()), args.env,
                         args.episodes, args.seed, args.json);
    return;
#else
    throw ConfigError("rollout: this build has no agents (libtorch), so no checkpoint policy");
#endif
  }
  if (args.env.empty()) {
    throw ConfigError("rollout: --env is required (unless --policy checkpoint:RUN_DIR)");
  }
  CheckPolicyName(args.policy);
  const nlohmann::json options = ParseEnvOptions(args.options);
  auto env = Make(args.env, options);
  if (const std::string note = PixelObservationNote(*env); !note.empty()) {
    std::cerr << args.env << ": " << note << "\n";
  }
  const EnvMaker make_env = [&] { return Make(args.env, options); };
  if (const auto groups = env->EvaluationTasks(); !groups.empty()) {
    RunGroupRollout(*env, make_env, groups, args);
    return;
  }
  const RolloutSummary summary = SeededRollout(*env, args.policy, args.seed, args.task_seed,
                                               args.episodes, args.threads, make_env);
  if (args.json) {
    PrintJson(summary.ToJson());
    return;
  }
  Table table({">episode", ">return", ">length", "success", "end"});
  for (size_t i = 0; i < summary.episodes.size(); ++i) {
    const EpisodeStats& e = summary.episodes[i];
    table.AddRow({std::to_string(i), Fixed(e.episode_return, 3), std::to_string(e.length),
                  e.success < 0 ? "-" : (e.success ? "yes" : "no"),
                  e.terminated ? "terminated" : "truncated"});
  }
  table.Print(std::cout);
  std::cout << args.env << ": " << summary.episodes.size() << " episodes, mean return "
            << Fixed(summary.mean_return, 3) << ", mean length " << Fixed(summary.mean_length, 1)
            << ", success rate " << SuccessRate(summary.success_rate) << "\n";
}

}  // namespace

void AddRolloutCommand(CLI::App& app, CommandContext& /*context*/) {
  auto args = std::make_shared<RolloutArgs>();
  CLI::App* cmd = app.add_subcommand("rollout", "Run seeded episodes of a policy in one env");
  cmd->add_option("--env", args->env,
                  "env id (see `manyworlds envs`); with a checkpoint policy, optional (the "
                  "run's env)");
  cmd->add_option("--policy", args->policy,
                  "policy: random, scripted (manipulation tasks and benchmarks), or "
                  "checkpoint:RUN_DIR (a trained run's latest checkpoint, or "
                  "checkpoint:RUN_DIR/checkpoints/step_N; deterministic actions on every task "
                  "of the run; for a meta-RL run, --episodes trials per held-out task of its "
                  "exploration episodes, adaptation and adapted episodes)")
      ->capture_default_str();
  cmd->add_option("--episodes", args->episodes, "number of episodes (>= 1); for a benchmark, the first N variations of each task")
      ->capture_default_str()
      ->check(AtLeastOne(1000000));
  cmd->add_option("--seed", args->seed, "env seed (dynamics, initial states; policy seed)")
      ->capture_default_str()
      ->check(Unsigned());
  cmd->add_option("--task-seed", args->task_seed, "task seed (which task is sampled)")
      ->capture_default_str()
      ->check(Unsigned());
  cmd->add_option("--option", args->options, "env option key=value (repeatable)");
  cmd->add_option("--threads", args->threads,
                  "threads running episodes at once (each with its own env copy); the results "
                  "do not depend on it")
      ->capture_default_str()
      ->check(AtLeastOne(kMaxThreads));
  cmd->add_flag("--json", args->json, "print the summary as JSON");
  cmd->callback([args] { RunRollout(*args); });
}

}  // namespace manyworlds::cli
