// manyworlds bench agent --algo sac|ppo|trpo|rl2|maml|pearl: full SAC updates per second
// (agents::MeasureSacUpdates) on random batches, or on-policy optimisation
// throughput (samples pushed through one PPO epoch: policy and value forward,
// backward and Adam over minibatches; for TRPO one whole policy step with
// its conjugate gradient and line search plus the value fit), with the
// thread configuration used.
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "apps/manyworlds/cli_util.h"
#include "apps/manyworlds/commands.h"
#include <algorithm>
#include <chrono>

#include "manyworlds/agents/maml/maml.h"
#include "manyworlds/agents/pearl/pearl.h"
#include "manyworlds/agents/ppo/ppo.h"
#include "manyworlds/agents/rl2/rl2.h"
#include "manyworlds/agents/sac.h"
#include "manyworlds/agents/sac_timing.h"
#include "manyworlds/agents/trpo/trpo.h"
#include "manyworlds/core/error.h"
#include "manyworlds/core/memory.h"
#include "manyworlds/core/registry.h"
#include "manyworlds/nn/threads.h"

namespace manyworlds::cli {
namespace {

struct BenchAgentArgs {
  std::string agent = "sac";
  int batch = 128;
  int minibatch = 1000;
  int hidden = 400;
  int layers = 3;
  int obs_dim = 39;
  int action_dim = 4;
  int tasks = 1;
  int trial_length = 200;  // rl2, maml: steps per trial
  std::string architecture = "mlp";
  bool pcgrad = false;
  bool disentangled_alpha = false;
  int updates = 20;
  int repeats = 5;
  int shards = 1;
  int update_threads = 0;  // 0: one per shard, at most one per core
  int torch_threads = 0;  // 0: the learner's default (nn::ConfigureTorchThreads)
  int blas_threads = 0;   // 0: the BLAS default (OPENBLAS_NUM_THREADS or one per core)
  uint64_t seed = 0;
  bool json = false;
};

std::string Join(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

// Samples per second through the on-policy optimisation on random data.
void RunBenchOnPolicy(const BenchAgentArgs& args) {
  agents::PolicySpaces spaces;
  spaces.obs_dim = args.obs_dim;
  spaces.action_dim = args.action_dim;
  spaces.num_tasks = args.tasks;
  std::unique_ptr<agents::PolicyGradientLearner> learner;
  agents::PpoLearner* ppo = nullptr;
  auto common = [&](agents::PolicyGradientConfig& c) {
    c.hidden_dim = args.hidden;
    c.num_layers = args.layers;
    c.vf_hidden_dim = args.hidden;
    c.vf_num_layers = args.layers;
    c.seed = args.seed;
    c.architecture = args.architecture;
    c.pcgrad = args.pcgrad;
  };
  if (args.agent == "ppo") {
    agents::PpoConfig c;
    common(c);
    c.minibatch_size = args.minibatch;
    auto p = std::make_unique<agents::PpoLearner>(c, spaces);
    ppo = p.get();
    learner = std::move(p);
  } else {
    agents::TrpoConfig c;
    common(c);
    c.vf_minibatch_size = args.minibatch;
    c.vf_epochs = 1;
    learner = std::make_unique<agents::TrpoLearner>(c, spaces);
  }
  if (args.torch_threads > 0 || args.blas_threads > 0) {
    nn::SetThreads(args.torch_threads > 0 ? args.torch_threads : 1, args.blas_threads);
  }
  torch::manual_seed(static_cast<uint64_t>(args.seed));
  const int64_t b = args.batch;
  rl::RolloutBuffer rollout(1, b, args.obs_dim, args.action_dim);
  rollout.obs.copy_(torch::randn(rollout.obs.sizes()));
  rollout.task_index.copy_(torch::randint(0, args.tasks, {b}, torch::kInt64));
  {
    agents::ActorState state;
    const agents::ActOutput out = learner->Act(rollout.obs[0], rollout.task_index, state,
                                               agents::ActMode::kSample);
    rollout.actions[0].copy_(out.action);
    rollout.log_probs[0].copy_(out.log_prob);
  }
  rollout.rewards.copy_(torch::randn(rollout.rewards.sizes()));
  rollout.ended.fill_(1.0f);
  using Clock = std::chrono::steady_clock;
  std::vector<double> samples;
  // PPO: one epoch = the unit; TRPO: one whole update (policy step + one value epoch)
  agents::PolicySamples ppo_samples;
  if (ppo != nullptr) {
    const torch::Tensor tasks = rollout.FlatTasks();
    ppo_samples.x = ppo->NetworkInput(rollout.FlatObs(), tasks);
    ppo_samples.obs = rollout.FlatObs();
    ppo_samples.tasks = tasks;
    ppo_samples.actions = rollout.FlatActions();
    ppo_samples.log_probs = rollout.log_probs.reshape({b});
    ppo_samples.advantages = torch::randn({b});
    ppo_samples.returns = torch::randn({b});
    ppo_samples.episode_steps = torch::zeros({b});
  }
  auto once = [&] {
    if (ppo != nullptr) {
      ppo->Epoch(ppo_samples);
    } else {
      learner->Update(rollout);
    }
  };
  once();  // warm-up
  for (int r = 0; r < args.repeats; ++r) {
    const auto t0 = Clock::now();
    for (int u = 0; u < args.updates; ++u) once();
    const double s = std::chrono::duration<double>(Clock::now() - t0).count();
    samples.push_back(static_cast<double>(b) * args.updates / s);
  }
  std::vector<double> sorted = samples;
  std::sort(sorted.begin(), sorted.end());
  const double median = sorted[sorted.size() / 2];
  const nn::ThreadInfo threads = nn::CurrentThreads();
  if (args.json) {
    PrintJson({{"agent", args.agent},
               {"batch", args.batch},
               {"minibatch", args.minibatch},
               {"hidden", args.hidden},
               {"layers", args.layers},
               {"obs_dim", args.obs_dim},
               {"action_dim", args.action_dim},
               {"tasks", args.tasks},
               {"architecture", args.architecture},
               {"pcgrad", args.pcgrad},
               {"unit", ppo != nullptr ? "one epoch (policy + value, minibatches)"
                                       : "one update (CG policy step + one value epoch)"},
               {"units_per_repeat", args.updates},
               {"repeats", args.repeats},
               {"samples_per_s", median},
               {"samples", samples},
               {"threads",
                {{"torch_intra_op", threads.torch_intra_op},
                 {"blas", threads.blas_threads},
                 {"blas_core", threads.blas_core}}}});
    return;
  }
  std::cout << args.agent << ": " << Fixed(median, 0) << " samples/s (median of "
            << samples.size() << " repeats), batch " << b << ", minibatch " << args.minibatch
            << ", " << args.layers << " x " << args.hidden << " tanh, obs " << args.obs_dim
            << ", action " << args.action_dim << ", " << args.architecture
            << (args.pcgrad ? " + pcgrad" : "") << "\n";
}

// The meta-learners' update on a random trial rollout: RL2's PPO epoch over
// whole trials (GRU unrolled, backpropagation through time, baseline fit,
// GAE) or MAML's outer TRPO step (inner steps with create_graph, CG on
// Fisher-vector products through them, one line-search candidate).
void RunBenchMeta(const BenchAgentArgs& args) {
  agents::PolicySpaces spaces;
  spaces.obs_dim = args.obs_dim;
  spaces.action_dim = args.action_dim;
  std::unique_ptr<agents::OnPolicyLearner> learner;
  if (args.agent == "rl2") {
    agents::Rl2Config c;
    c.hidden_dim = args.hidden;
    c.epochs = 1;
    c.minibatch_trials = args.minibatch;
    c.episodes_per_trial = 1;
    c.seed = args.seed;
    learner = std::make_unique<agents::Rl2Learner>(c, spaces);
  } else {
    agents::MamlConfig c;
    c.hidden_dim = args.hidden;
    c.num_layers = args.layers;
    c.episodes_per_task = 1;
    c.max_backtracks = 1;  // one candidate: the same work on every update
    c.seed = args.seed;
    learner = std::make_unique<agents::MamlLearner>(c, spaces);
  }
  if (args.torch_threads > 0 || args.blas_threads > 0) {
    nn::SetThreads(args.torch_threads > 0 ? args.torch_threads : 1, args.blas_threads);
  }
  torch::manual_seed(static_cast<uint64_t>(args.seed));
  const int64_t n = args.batch, t_len = args.trial_length;
  if (args.agent == "maml" && t_len % 2 != 0) {
    throw ConfigError("--trial-length must be even for maml (half before, half after adaptation)");
  }
  rl::RolloutBuffer rollout(t_len, n, args.obs_dim, args.action_dim);
  rollout.obs.copy_(torch::randn(rollout.obs.sizes()));
  rollout.actions.copy_(torch::randn(rollout.actions.sizes()));
  rollout.log_probs.copy_(torch::randn(rollout.log_probs.sizes()) - 4.0);
  rollout.rewards.copy_(torch::randn(rollout.rewards.sizes()));
  rollout.ended.zero_();
  rollout.ended[t_len - 1].fill_(1.0f);
  if (args.agent == "maml") rollout.ended[t_len / 2 - 1].fill_(1.0f);
  using Clock = std::chrono::steady_clock;
  learner->Update(rollout);  // warm-up
  std::vector<double> rates;
  for (int r = 0; r < args.repeats; ++r) {
    const auto t0 = Clock::now();
    for (int u = 0; u < args.updates; ++u) learner->Update(rollout);
    const double sec = std::chrono::duration<double>(Clock::now() - t0).count();
    rates.push_back(args.updates / sec);
  }
  std::vector<double> sorted = rates;
  std::sort(sorted.begin(), sorted.end());
  const double median = sorted[sorted.size() / 2];
  const nn::ThreadInfo threads = nn::CurrentThreads();
  const std::string unit = args.agent == "rl2"
                               ? "one PPO epoch over the trials (minibatches of --minibatch trials)"
                               : "one outer TRPO step (10 CG iterations, one line-search candidate)";
  if (args.json) {
    PrintJson({{"agent", args.agent},
               {"trials", n},
               {"trial_length", t_len},
               {"minibatch", args.minibatch},
               {"hidden", args.hidden},
               {"layers", args.layers},
               {"obs_dim", args.obs_dim},
               {"action_dim", args.action_dim},
               {"unit", unit},
               {"updates_per_s", median},
               {"samples_per_s", median * static_cast<double>(n * t_len)},
               {"updates", rates},
               {"threads",
                {{"torch_intra_op", threads.torch_intra_op},
                 {"blas", threads.blas_threads},
                 {"blas_core", threads.blas_core}}}});
    return;
  }
  std::cout << args.agent << ": " << Fixed(median, 2) << " updates/s ("
            << Fixed(median * static_cast<double>(n * t_len), 0) << " samples/s), " << n
            << " trials of " << t_len << " steps; " << unit << "\n";
}

// PEARL's update on random per-task batches: --tasks tasks (the
// meta-batch), each with --minibatch context and --batch RL transitions;
// encoder 3 x 200 (oyster's), policy, twin Q and V --layers x --hidden.
void RunBenchPearl(const BenchAgentArgs& args) {
  agents::PearlConfig c;
  c.hidden_dim = args.hidden;
  c.num_layers = args.layers;
  c.meta_batch = args.tasks;
  c.batch_size = args.batch;
  c.embedding_batch_size = args.minibatch;
  c.seed = args.seed;
  c.Validate();
  agents::PearlLearner learner(c, args.obs_dim, args.action_dim);
  if (args.torch_threads > 0 || args.blas_threads > 0) {
    nn::SetThreads(args.torch_threads > 0 ? args.torch_threads : 1, args.blas_threads);
  }
  torch::manual_seed(static_cast<uint64_t>(args.seed));
  auto random_batch = [&](int64_t rows) {
    agents::Batch b;
    b.obs = torch::randn({rows, args.obs_dim});
    b.action = torch::rand({rows, args.action_dim}) * 2 - 1;
    b.reward = torch::randn({rows});
    b.next_obs = torch::randn({rows, args.obs_dim});
    b.done = torch::zeros({rows});
    b.task_index = torch::zeros({rows}, torch::kInt64);
    return b;
  };
  const agents::Batch context = random_batch(int64_t{args.tasks} * args.minibatch);
  const agents::Batch rl = random_batch(int64_t{args.tasks} * args.batch);
  using Clock = std::chrono::steady_clock;
  for (int w = 0; w < 3; ++w) learner.Update(context, rl, args.tasks);  // warm-up
  std::vector<double> rates;
  for (int r = 0; r < args.repeats; ++r) {
    const auto t0 = Clock::now();
    for (int u = 0; u < args.updates; ++u) learner.Update(context, rl, args.tasks);
    rates.push_back(args.updates / std::chrono::duration<double>(Clock::now() - t0).count());
  }
  std::vector<double> sorted = rates;
  std::sort(sorted.begin(), sorted.end());
  const double median = sorted[sorted.size() / 2];
  const nn::ThreadInfo threads = nn::CurrentThreads();
  if (args.json) {
    PrintJson({{"agent", "pearl"},
               {"tasks", args.tasks},
               {"batch", args.batch},
               {"context", args.minibatch},
               {"hidden", args.hidden},
               {"layers", args.layers},
               {"obs_dim", args.obs_dim},
               {"action_dim", args.action_dim},
               {"unit", "one update (encoder + KL, twin Q, V and target V, policy)"},
               {"updates_per_s", median},
               {"ms_per_update", 1000.0 / median},
               {"updates", rates},
               {"threads",
                {{"torch_intra_op", threads.torch_intra_op},
                 {"blas", threads.blas_threads},
                 {"blas_core", threads.blas_core}}}});
    return;
  }
  std::cout << "pearl: " << Fixed(median, 1) << " updates/s, " << Fixed(1000.0 / median, 2)
            << " ms/update (median of " << rates.size() << " repeats of " << args.updates
            << "); " << args.tasks << " tasks x (" << args.batch << " RL + " << args.minibatch
            << " context) transitions, " << args.layers << " x " << args.hidden << ", obs "
            << args.obs_dim << ", action " << args.action_dim << "\n";
}

// Rough upper bound of what one update holds at once: inputs and outputs of
// every layer for each row (forward, gradients, optimizer copies), weights
// with their gradients and Adam moments. Refuses sizes that cannot fit.
void CheckBenchMemory(const BenchAgentArgs& args) {
  double rows = static_cast<double>(args.batch);
  if (args.agent == "rl2" || args.agent == "maml") rows *= args.trial_length;
  if (args.agent == "sac" || args.agent == "pearl") rows *= args.tasks;
  const double width = std::max(args.obs_dim, args.hidden);
  const double per_row = 2.0 * args.obs_dim + 8.0 * args.hidden * (args.layers + 1);
  const double weights = 16.0 * width * args.hidden * (args.layers + 1);
  CheckMemoryEstimate(4.0 * (rows * per_row + weights), "bench agent at these sizes",
                      "--batch, --tasks, --trial-length, --hidden or --obs-dim");
}

void RunBenchAgent(const BenchAgentArgs& args) {
  CheckBenchMemory(args);
  if (args.agent == "pearl") {
    RunBenchPearl(args);
    return;
  }
  if (args.agent == "ppo" || args.agent == "trpo") {
    RunBenchOnPolicy(args);
    return;
  }
  if (args.agent == "rl2" || args.agent == "maml") {
    RunBenchMeta(args);
    return;
  }
  if (args.agent != "sac") {
    throw ConfigError("--algo: unknown algorithm '" + args.agent + "'" +
                      SuggestNearest(args.agent, {"sac", "ppo", "trpo", "rl2", "maml", "pearl"}) +
                      "; allowed: sac, ppo, trpo, rl2, maml, pearl");
  }
  agents::SacConfig config;
  config.batch_size = args.batch;
  config.hidden_dim = args.hidden;
  config.num_layers = args.layers;
  config.architecture = args.architecture;
  config.pcgrad = args.pcgrad;
  config.disentangled_alpha = args.disentangled_alpha;
  config.seed = args.seed;
  config.update_shards = args.shards;
  config.update_threads = args.update_threads;
  try {
    config.Validate();
  } catch (const ConfigError& e) {
    // Name the flag rather than the config field.
    if (config.architecture != args.architecture ||
        std::string(e.what()).find("architecture") != std::string::npos) {
      throw ConfigError("--architecture must be one of " + Join(agents::SacArchitectures()) +
                        ", got '" + args.architecture + "'");
    }
    throw;
  }
  if (args.torch_threads > 0 || args.blas_threads > 0) {
    nn::SetThreads(args.torch_threads > 0 ? args.torch_threads : 1, args.blas_threads);
  }
  const agents::SacTimingResult r = agents::MeasureSacUpdates(
      config, args.obs_dim, args.action_dim, args.tasks, args.updates, args.repeats);
  const nn::ThreadInfo threads = nn::CurrentThreads();
  if (args.json) {
    PrintJson({{"agent", args.agent},
               {"architecture", args.architecture},
               {"pcgrad", args.pcgrad},
               {"disentangled_alpha", args.disentangled_alpha},
               {"batch", args.batch},
               {"hidden", args.hidden},
               {"layers", args.layers},
               {"obs_dim", args.obs_dim},
               {"action_dim", args.action_dim},
               {"tasks", args.tasks},
               {"updates_per_repeat", args.updates},
               {"repeats", args.repeats},
               {"updates_per_s", r.updates_per_s},
               {"ms_per_update", 1000.0 / r.updates_per_s},
               {"samples", r.samples},
               {"update_shards", args.shards},
               {"update_threads", r.update_threads},
               {"threads",
                {{"torch_intra_op", threads.torch_intra_op},
                 {"torch_inter_op", threads.torch_inter_op},
                 {"blas", threads.blas_threads},
                 {"blas_core", threads.blas_core},
                 {"blas_library", threads.blas}}}});
    return;
  }
  std::cout << "sac (" << args.architecture << (args.pcgrad ? " + pcgrad" : "") << ", "
            << args.tasks << " task" << (args.tasks == 1 ? "" : "s") << "): "
            << Fixed(r.updates_per_s, 1) << " updates/s, " << Fixed(1000.0 / r.updates_per_s, 2)
            << " ms/update (median of " << r.samples.size() << " repeats of " << args.updates
            << " updates)\nbatch " << args.batch << ", " << args.layers << " x " << args.hidden
            << ", obs " << args.obs_dim << ", action " << args.action_dim
            << "\nshards: " << args.shards << " on " << r.update_threads << " thread"
            << (r.update_threads == 1 ? "" : "s") << "; torch intra-op " << threads.torch_intra_op << ", inter-op "
            << threads.torch_inter_op << "; BLAS "
            << (threads.blas_threads < 0 ? std::string("?") : std::to_string(threads.blas_threads))
            << " (" << threads.blas << "; kernels " << threads.blas_core << ")\nsamples:";
  for (double s : r.samples) std::cout << " " << Fixed(s, 1);
  std::cout << "\n";
}

}  // namespace

void AddBenchAgentSubcommand(CLI::App& bench, CommandContext&) {
  auto args = std::make_shared<BenchAgentArgs>();
  CLI::App* cmd = bench.add_subcommand(
      "agent",
      "Agent updates per second: full SAC updates (critic, actor, temperature, targets) on\n"
      "random batches of the given sizes; the observation carries no task id, the\n"
      "learner conditions on the task index per --architecture");
  cmd->add_option("--algo,--agent", args->agent, "algorithm to time: sac, ppo, trpo, rl2, maml, pearl")
      ->capture_default_str();
  cmd->add_option("--trial-length", args->trial_length,
                  "rl2, maml: steps per trial (maml: half before, half after adaptation)")
      ->capture_default_str()
      ->check(AtLeastOne(100000));
  cmd->add_option("--batch", args->batch,
                  "batch size (ppo/trpo: samples in the rollout; rl2/maml: trials; pearl: RL "
                  "transitions per task)")
      ->capture_default_str()
      ->check(AtLeastOne(1000000));
  cmd->add_option("--minibatch", args->minibatch,
                  "ppo: minibatch size of the epoch; trpo: of the value fit; rl2: trials; pearl: "
                  "context transitions per task")
      ->capture_default_str()
      ->check(AtLeastOne(1000000));
  cmd->add_option("--hidden", args->hidden, "hidden width of actor and critics")
      ->capture_default_str()
      ->check(AtLeastOne(16384));
  cmd->add_option("--layers", args->layers, "hidden layers of actor and critics")
      ->capture_default_str()
      ->check(AtLeastOne(64));
  cmd->add_option("--obs-dim", args->obs_dim, "observation size (without any task id)")
      ->capture_default_str()
      ->check(AtLeastOne(100000));
  cmd->add_option("--action-dim", args->action_dim, "action size")
      ->capture_default_str()
      ->check(AtLeastOne(4096));
  cmd->add_option("--tasks", args->tasks, "number of tasks (batches draw task indices uniformly; pearl: the meta-batch)")
      ->capture_default_str()
      ->check(AtLeastOne(10000));
  cmd->add_option("--architecture", args->architecture,
                  "task conditioning: " + Join(agents::SacArchitectures()))
      ->capture_default_str();
  cmd->add_flag("--pcgrad", args->pcgrad,
                "combine per-task gradients with PCGrad (one backward per task in the batch)");
  cmd->add_flag("--disentangled-alpha", args->disentangled_alpha, "one temperature per task");
  cmd->add_option("--updates", args->updates, "timed updates per repeat (after 3 warm-up updates)")
      ->capture_default_str()
      ->check(AtLeastOne(1000000));
  cmd->add_option("--repeats", args->repeats, "timed repeats (the median is reported)")
      ->capture_default_str()
      ->check(AtLeastOne(10000));
  cmd->add_option("--shards", args->shards,
                  "data-parallel shards of each update (SacConfig update_shards)")
      ->capture_default_str()
      ->check(AtLeastOne());
  cmd->add_option("--update-threads", args->update_threads,
                  "threads running the shards (0: one per shard, at most one per core)")
      ->capture_default_str()
      ->check(Unsigned());
  cmd->add_option("--torch-threads", args->torch_threads,
                  "libtorch intra-op threads (default: 1, as every learner sets)")
      ->check(AtLeastOne());
  cmd->add_option("--blas-threads", args->blas_threads,
                  "OpenBLAS threads (default: OPENBLAS_NUM_THREADS, else one per core); at most "
                  "one of --torch-threads and --blas-threads may be > 1")
      ->check(AtLeastOne());
  cmd->add_option("--seed", args->seed, "seed of the networks and the random batches")
      ->capture_default_str()
      ->check(Unsigned());
  cmd->add_flag("--json", args->json,
                "print JSON: updates_per_s (median), samples, ms_per_update, the configuration "
                "and the threads used");
  cmd->callback([args] { RunBenchAgent(*args); });
}

}  // namespace manyworlds::cli
