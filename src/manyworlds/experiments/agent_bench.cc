// The registry's agent benchmarks (`manyworlds bench agent --algo NAME`):
// each times one algorithm's update on random data of the given sizes and
// returns the figures as JSON and as one human line. The rows of the
// algorithm registry (algorithms.cc) point at these functions.
#include "manyworlds/experiments/agent_bench.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <memory>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include "manyworlds/agents/deepmdp/deepmdp.h"
#include "manyworlds/agents/distral/distral.h"
#include "manyworlds/agents/hipbmdp/hipbmdp.h"
#include "manyworlds/agents/maml/maml.h"
#include "manyworlds/agents/pearl/pearl.h"
#include "manyworlds/agents/ppo/ppo.h"
#include "manyworlds/agents/rl2/rl2.h"
#include "manyworlds/agents/sac/sac.h"
#include "manyworlds/agents/sac/sac_timing.h"
#include "manyworlds/agents/sac_ae/sac_ae.h"
#include "manyworlds/agents/te_ppo/te_ppo.h"
#include "manyworlds/agents/trpo/trpo.h"
#include "manyworlds/core/error.h"
#include "manyworlds/core/median.h"
#include "manyworlds/core/memory.h"
#include "manyworlds/nn/threads.h"

namespace manyworlds::experiments {
namespace {

using Clock = std::chrono::steady_clock;

std::string Fixed(double value, int digits) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.*f", digits, value);
  return buffer;
}

std::string Join(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

void ApplyThreads(const AgentBenchSizes& args) {
  if (args.torch_threads > 0 || args.blas_threads > 0) {
    nn::SetThreads(args.torch_threads > 0 ? args.torch_threads : 1, args.blas_threads);
  }
}

// Calls per second of `repeats` timed runs of `updates` calls each, after
// `warmup` untimed calls.
std::vector<double> TimeRepeats(const AgentBenchSizes& args, int warmup,
                                const std::function<void()>& once) {
  for (int w = 0; w < warmup; ++w) once();
  std::vector<double> rates;
  for (int r = 0; r < args.repeats; ++r) {
    const auto t0 = Clock::now();
    for (int u = 0; u < args.updates; ++u) once();
    rates.push_back(args.updates / std::chrono::duration<double>(Clock::now() - t0).count());
  }
  return rates;
}

nlohmann::json ThreadsJson() {
  const nn::ThreadInfo threads = nn::CurrentThreads();
  return {{"torch_intra_op", threads.torch_intra_op},
          {"blas", threads.blas_threads},
          {"blas_core", threads.blas_core},
          {"gemm", threads.gemm}};
}

template <class Config>
Config PolicyGradientBenchConfig(const AgentBenchSizes& args) {
  Config c;
  c.hidden_dim = args.hidden;
  c.num_layers = args.layers;
  c.vf_hidden_dim = args.hidden;
  c.vf_num_layers = args.layers;
  c.seed = args.seed;
  c.architecture = args.architecture;
  c.pcgrad = args.pcgrad;
  return c;
}

// Samples per second through an on-policy optimisation on random data: PPO's
// unit is one epoch (`ppo` set), the others' one whole Update (TRPO: policy
// step + one value epoch).
AgentBenchResult TimeOnPolicy(const std::string& algo, const AgentBenchSizes& args,
                              agents::OnPolicyLearner& learner_ref, agents::PpoLearner* ppo,
                              const std::string& unit) {
  agents::OnPolicyLearner* learner = &learner_ref;
  ApplyThreads(args);
  torch::manual_seed(static_cast<uint64_t>(args.seed));
  const int64_t b = args.batch;
  rl::RolloutBuffer rollout(1, b, args.obs_dim, args.action_dim);
  rollout.obs.copy_(torch::randn(rollout.obs.sizes()));
  rollout.task_index.copy_(torch::randint(0, args.tasks, {b}, torch::kInt64));
  {
    agents::ActorState state;
    agents::Actor& actor = learner->AsActor();
    state = actor.Initial(b);
    const agents::ActOutput out =
        actor.Act(rollout.obs[0], rollout.task_index, state, agents::ActMode::kSample);
    rollout.actions[0].copy_(out.action);
    rollout.log_probs[0].copy_(out.log_prob);
    if (out.latent.defined()) rollout.latents = out.latent.unsqueeze(0).clone();
  }
  rollout.rewards.copy_(torch::randn(rollout.rewards.sizes()));
  rollout.ended.fill_(1.0f);
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
  std::vector<double> samples = TimeRepeats(args, 1, [&] {
    if (ppo != nullptr) {
      ppo->Epoch(ppo_samples);
    } else {
      learner->Update(rollout);
    }
  });
  for (double& s : samples) s *= static_cast<double>(b);
  const double median = Median(samples);
  AgentBenchResult result;
  result.json = nlohmann::json({{"agent", algo},
                                {"batch", args.batch},
                                {"minibatch", args.minibatch},
                                {"hidden", args.hidden},
                                {"layers", args.layers},
                                {"obs_dim", args.obs_dim},
                                {"action_dim", args.action_dim},
                                {"tasks", args.tasks},
                                {"architecture", args.architecture},
                                {"pcgrad", args.pcgrad},
                                {"unit", unit},
                                {"units_per_repeat", args.updates},
                                {"repeats", args.repeats},
                                {"samples_per_s", median},
                                {"samples", samples},
                                {"threads", ThreadsJson()}});
  std::ostringstream summary;
  summary << algo << ": " << Fixed(median, 0) << " samples/s (median of " << samples.size()
          << " repeats), batch " << b << ", minibatch " << args.minibatch << ", " << args.layers
          << " x " << args.hidden << " tanh, obs " << args.obs_dim << ", action " << args.action_dim
          << ", " << args.architecture << (args.pcgrad ? " + pcgrad" : "") << "\n";
  result.summary = summary.str();
  return result;
}

}  // namespace

// Rough upper bound of what one update holds at once: inputs and outputs of
// every layer for each row (forward, gradients, optimizer copies), weights
// with their gradients and Adam moments. Refuses sizes that cannot fit.
void CheckBenchMemory(const AgentBenchSizes& args, double rows) {
  const double width = std::max(args.obs_dim, args.hidden);
  const double per_row = 2.0 * args.obs_dim + 8.0 * args.hidden * (args.layers + 1);
  const double weights = 16.0 * width * args.hidden * (args.layers + 1);
  CheckMemoryEstimate(4.0 * (rows * per_row + weights), "bench agent at these sizes",
                      "--batch, --tasks, --trial-length, --hidden or --obs-dim");
}

agents::PolicySpaces BenchSpaces(const AgentBenchSizes& args) {
  agents::PolicySpaces spaces;
  spaces.obs_dim = args.obs_dim;
  spaces.action_dim = args.action_dim;
  spaces.num_tasks = args.tasks;
  return spaces;
}

AgentBenchResult TimeOnPolicyUpdates(const std::string& algo, const AgentBenchSizes& sizes,
                                     agents::OnPolicyLearner& learner, const std::string& unit) {
  return TimeOnPolicy(algo, sizes, learner, nullptr, unit);
}

AgentBenchResult BenchPpoUpdates(const std::string& algo, const AgentBenchSizes& args) {
  CheckBenchMemory(args, args.batch);
  auto c = PolicyGradientBenchConfig<agents::PpoConfig>(args);
  c.minibatch_size = args.minibatch;
  agents::PpoLearner learner(c, BenchSpaces(args));
  return TimeOnPolicy(algo, args, learner, &learner, "one epoch (policy + value, minibatches)");
}

AgentBenchResult BenchTrpoUpdates(const std::string& algo, const AgentBenchSizes& args) {
  CheckBenchMemory(args, args.batch);
  auto c = PolicyGradientBenchConfig<agents::TrpoConfig>(args);
  c.vf_minibatch_size = args.minibatch;
  c.vf_epochs = 1;
  agents::TrpoLearner learner(c, BenchSpaces(args));
  return TimeOnPolicy(algo, args, learner, nullptr,
                      "one update (CG policy step + one value epoch)");
}

AgentBenchResult BenchTePpoUpdates(const std::string& algo, const AgentBenchSizes& args) {
  CheckBenchMemory(args, args.batch);
  auto c = PolicyGradientBenchConfig<agents::TePpoConfig>(args);
  c.minibatch_size = args.minibatch;
  c.epochs = 1;
  c.inference_epochs = 1;
  agents::TePpoLearner learner(c, BenchSpaces(args));
  return TimeOnPolicy(algo, args, learner, nullptr,
                      "one update (one epoch of policy, encoder, inference network and "
                      "value)");
}

namespace {

// The meta-learners' update on a random trial rollout of --batch trials of
// --trial-length steps (`halves`: the trial is two episodes, before and after
// adaptation).
AgentBenchResult TimeTrialUpdates(const std::string& algo, const AgentBenchSizes& args,
                                  agents::OnPolicyLearner& learner_ref, bool halves,
                                  const std::string& unit) {
  agents::OnPolicyLearner* learner = &learner_ref;
  ApplyThreads(args);
  torch::manual_seed(static_cast<uint64_t>(args.seed));
  const int64_t n = args.batch, t_len = args.trial_length;
  if (halves && t_len % 2 != 0) {
    throw ConfigError("--trial-length must be even for " + algo +
                      " (half before, half after adaptation)");
  }
  rl::RolloutBuffer rollout(t_len, n, args.obs_dim, args.action_dim);
  rollout.obs.copy_(torch::randn(rollout.obs.sizes()));
  rollout.actions.copy_(torch::randn(rollout.actions.sizes()));
  rollout.log_probs.copy_(torch::randn(rollout.log_probs.sizes()) - 4.0);
  rollout.rewards.copy_(torch::randn(rollout.rewards.sizes()));
  rollout.ended.zero_();
  rollout.ended[t_len - 1].fill_(1.0f);
  if (halves) rollout.ended[t_len / 2 - 1].fill_(1.0f);
  const std::vector<double> rates = TimeRepeats(args, 1, [&] { learner->Update(rollout); });
  const double median = Median(rates);
  AgentBenchResult result;
  result.json = nlohmann::json({{"agent", algo},
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
                                {"threads", ThreadsJson()}});
  std::ostringstream summary;
  summary << algo << ": " << Fixed(median, 2) << " updates/s ("
          << Fixed(median * static_cast<double>(n * t_len), 0) << " samples/s), " << n
          << " trials of " << t_len << " steps; " << unit << "\n";
  result.summary = summary.str();
  return result;
}

// A meta-learner's config with the sizes of the benchmark, its learner, and
// its update on random trials.
template <class Learner, class Config>
AgentBenchResult BenchTrials(const std::string& algo, const AgentBenchSizes& args, Config c,
                             bool halves, const std::string& unit) {
  CheckBenchMemory(args, static_cast<double>(args.batch) * args.trial_length);
  c.hidden_dim = args.hidden;
  if constexpr (requires { c.num_layers; }) c.num_layers = args.layers;
  c.seed = args.seed;
  Learner learner(c, BenchSpaces(args));
  return TimeTrialUpdates(algo, args, learner, halves, unit);
}

}  // namespace

// RL2's update: one PPO epoch over whole trials (GRU unrolled,
// backpropagation through time, baseline fit, GAE).
AgentBenchResult BenchRl2Updates(const std::string& algo, const AgentBenchSizes& args) {
  agents::Rl2Config c;
  c.epochs = 1;
  c.minibatch_trials = args.minibatch;
  c.episodes_per_trial = 1;
  return BenchTrials<agents::Rl2Learner>(
      algo, args, c, false, "one PPO epoch over the trials (minibatches of --minibatch trials)");
}

// MAML's outer TRPO step: inner steps with create_graph, CG on Fisher-vector
// products through them, one line-search candidate.
AgentBenchResult BenchMamlUpdates(const std::string& algo, const AgentBenchSizes& args) {
  agents::MamlConfig c;
  c.episodes_per_task = 1;
  c.max_backtracks = 1;  // one candidate: the same work on every update
  return BenchTrials<agents::MamlLearner>(
      algo, args, c, true, "one outer TRPO step (10 CG iterations, one line-search candidate)");
}

// PEARL's update on random per-task batches: --tasks tasks (the
// meta-batch), each with --minibatch context and --batch RL transitions;
// encoder 3 x 200 (oyster's), policy, twin Q and V --layers x --hidden.
AgentBenchResult BenchPearlUpdates(const std::string& algo, const AgentBenchSizes& args) {
  CheckBenchMemory(args, static_cast<double>(args.batch) * args.tasks);
  agents::PearlConfig c;
  c.hidden_dim = args.hidden;
  c.num_layers = args.layers;
  c.meta_batch = args.tasks;
  c.batch_size = args.batch;
  c.embedding_batch_size = args.minibatch;
  c.seed = args.seed;
  c.Validate();
  agents::PearlLearner learner(c, args.obs_dim, args.action_dim);
  ApplyThreads(args);
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
  const std::vector<double> rates =
      TimeRepeats(args, 3, [&] { learner.Update(context, rl, args.tasks); });
  const double median = Median(rates);
  AgentBenchResult result;
  result.json =
      nlohmann::json({{"agent", algo},
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
                      {"threads", ThreadsJson()}});
  std::ostringstream summary;
  summary << algo << ": " << Fixed(median, 1) << " updates/s, " << Fixed(1000.0 / median, 2)
          << " ms/update (median of " << rates.size() << " repeats of " << args.updates << "); "
          << args.tasks << " tasks x (" << args.batch << " RL + " << args.minibatch
          << " context) transitions, " << args.layers << " x " << args.hidden << ", obs "
          << args.obs_dim << ", action " << args.action_dim << "\n";
  result.summary = summary.str();
  return result;
}

// Full SAC updates per second (agents::MeasureSacUpdates) on random batches.
AgentBenchResult BenchSacUpdates(const std::string& algo, const AgentBenchSizes& args) {
  CheckBenchMemory(args, static_cast<double>(args.batch) * args.tasks);
  agents::SacConfig config;
  config.batch_size = args.batch;
  config.hidden_dim = args.hidden;
  config.num_layers = args.layers;
  config.architecture = args.architecture;
  config.pcgrad = args.pcgrad;
  config.gradnorm = args.gradnorm;
  config.disentangled_alpha = args.disentangled_alpha;
  config.seed = args.seed;
  config.update_shards = args.shards;
  config.update_threads = args.update_threads;
  try {
    config.Validate();
  } catch (const ConfigError& e) {
    // Name the flag rather than the config field.
    if (config.architecture != args.architecture ||
        std::string(e.what()).rfind("SacConfig.architecture", 0) == 0) {
      throw ConfigError("--architecture must be one of " + Join(agents::SacArchitectures()) +
                        ", got '" + args.architecture + "'");
    }
    throw;
  }
  ApplyThreads(args);
  const agents::SacTimingResult r = agents::MeasureSacUpdates(
      config, args.obs_dim, args.action_dim, args.tasks, args.updates, args.repeats);
  const nn::ThreadInfo threads = nn::CurrentThreads();
  AgentBenchResult result;
  result.json = nlohmann::json({{"agent", algo},
                                {"architecture", args.architecture},
                                {"pcgrad", args.pcgrad},
                                {"gradnorm", args.gradnorm},
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
                                {"params",
                                 {{"actor", r.actor_params},
                                  {"critics", r.critic_params},
                                  {"task_encoder", r.task_encoder_params},
                                  {"mixture_encoder", r.mixture_params}}},
                                {"threads",
                                 {{"torch_intra_op", threads.torch_intra_op},
                                  {"torch_inter_op", threads.torch_inter_op},
                                  {"blas", threads.blas_threads},
                                  {"blas_core", threads.blas_core},
                                  {"blas_library", threads.blas},
                                  {"gemm", threads.gemm}}}});
  std::ostringstream summary;
  summary << "sac (" << args.architecture << (args.pcgrad ? " + pcgrad" : "")
          << (args.gradnorm ? " + gradnorm" : "") << ", " << args.tasks
          << " task" << (args.tasks == 1 ? "" : "s") << "): " << Fixed(r.updates_per_s, 1)
          << " updates/s, " << Fixed(1000.0 / r.updates_per_s, 2) << " ms/update (median of "
          << r.samples.size() << " repeats of " << args.updates << " updates)\nbatch " << args.batch
          << ", " << args.layers << " x " << args.hidden << ", obs " << args.obs_dim << ", action "
          << args.action_dim << "\nshards: " << args.shards << " on " << r.update_threads
          << " thread" << (r.update_threads == 1 ? "" : "s") << "; torch intra-op "
          << threads.torch_intra_op << ", inter-op " << threads.torch_inter_op << "; BLAS "
          << (threads.blas_threads < 0 ? std::string("?") : std::to_string(threads.blas_threads))
          << " (" << threads.blas << "; kernels " << threads.blas_core << "); products on "
          << (threads.gemm == "onednn" ? "oneDNN" : "the BLAS") << "\nsamples:";
  for (double s : r.samples) summary << " " << Fixed(s, 1);
  summary << "\n";
  result.summary = summary.str();
  return result;
}

}  // namespace manyworlds::experiments

namespace manyworlds::experiments {

namespace {

// Four random replay batches of --batch rows per task (task index row % tasks), cycled by the
// off-policy benches so that data generation is not timed; with pixel_size > 0 also random
// frames of that many bytes.
std::vector<agents::Batch> RandomReplayBatches(const AgentBenchSizes& args, int64_t pixel_size) {
  at::Generator gen = at::detail::createCPUGenerator(args.seed + 1);
  const int64_t b = static_cast<int64_t>(args.batch) * args.tasks;
  std::vector<agents::Batch> batches;
  for (int i = 0; i < 4; ++i) {
    agents::Batch batch;
    batch.obs = torch::randn({b, args.obs_dim}, gen, torch::kFloat32);
    batch.action = torch::rand({b, args.action_dim}, gen, torch::kFloat32) * 2.0 - 1.0;
    batch.reward = torch::randn({b}, gen, torch::kFloat32);
    batch.next_obs = torch::randn({b, args.obs_dim}, gen, torch::kFloat32);
    batch.done = torch::zeros({b});
    batch.task_index = torch::arange(b, torch::kInt64) % args.tasks;
    if (pixel_size > 0) {
      batch.pixels = torch::randint(0, 256, {b, pixel_size}, gen, torch::kUInt8);
      batch.next_pixels = torch::randint(0, 256, {b, pixel_size}, gen, torch::kUInt8);
    }
    batches.push_back(std::move(batch));
  }
  return batches;
}

}  // namespace

AgentBenchResult BenchDistralUpdates(const std::string& algo, const AgentBenchSizes& args) {
  CheckBenchMemory(args, static_cast<double>(args.batch) * args.tasks);
  agents::DistralConfig config;
  config.hidden_dim = args.hidden;
  config.num_layers = args.layers;
  config.seed = args.seed;
  ApplyThreads(args);
  agents::DistralLearner learner(config, args.obs_dim, args.action_dim, args.tasks);
  const std::vector<agents::Batch> batches = RandomReplayBatches(args, 0);
  int next = 0;
  const std::vector<double> rates =
      TimeRepeats(args, 3, [&] { learner.Update(batches[static_cast<size_t>(next++ % 4)]); });
  const double median = Median(rates);
  AgentBenchResult result;
  result.json = nlohmann::json({{"agent", algo},
                                {"tasks", args.tasks},
                                {"batch_per_task", args.batch},
                                {"hidden", args.hidden},
                                {"layers", args.layers},
                                {"obs_dim", args.obs_dim},
                                {"action_dim", args.action_dim},
                                {"unit", "one update (every task agent's SAC update, one "
                                         "distillation step)"},
                                {"updates_per_s", median},
                                {"ms_per_update", 1000.0 / median},
                                {"updates", rates},
                                {"threads", ThreadsJson()}});
  std::ostringstream summary;
  summary << algo << ": " << Fixed(median, 2) << " updates/s, " << Fixed(1000.0 / median, 2)
          << " ms/update (median of " << rates.size() << " repeats of " << args.updates << "); "
          << args.tasks << " task agents x " << args.batch << " rows, " << args.layers << " x "
          << args.hidden << ", obs " << args.obs_dim << ", action " << args.action_dim << "\n";
  result.summary = summary.str();
  return result;
}

namespace {

// A pixel learner's whole update (SAC on the frames and its representation losses) on random
// frames of --channels x --frame x --frame.
template <class Learner, class Config>
AgentBenchResult TimePixelUpdates(const std::string& algo, const AgentBenchSizes& args,
                                  const std::string& unit) {
  // rows of frames as float feature maps (about 16 floats a byte, obs and next obs), in
  // hidden-layer equivalents
  CheckBenchMemory(args, static_cast<double>(args.batch) * args.tasks *
                             (1.0 + 32.0 * args.channels * args.frame * args.frame /
                                        (16.0 * args.hidden * (args.layers + 1.0))));
  Config config;
  config.hidden_dim = args.hidden;
  config.num_layers = args.layers;
  if constexpr (!std::is_same_v<Config, agents::HipBmdpConfig>) {
    config.architecture = args.architecture;
  }
  config.disentangled_alpha = args.disentangled_alpha;
  config.seed = args.seed;
  ApplyThreads(args);
  const std::vector<int64_t> frames = {args.channels, args.frame, args.frame};
  Learner learner(config, args.obs_dim, args.action_dim, args.tasks, frames);
  const int64_t b = static_cast<int64_t>(args.batch) * args.tasks;
  const std::vector<agents::Batch> batches = RandomReplayBatches(
      args, static_cast<int64_t>(args.channels) * args.frame * args.frame);
  int next = 0;
  const std::vector<double> rates =
      TimeRepeats(args, 3, [&] { learner.Update(batches[static_cast<size_t>(next++ % 4)]); });
  const double median = Median(rates);
  AgentBenchResult result;
  result.json = nlohmann::json(
      {{"agent", algo},
       {"tasks", args.tasks},
       {"batch", b},
       {"frame", {args.channels, args.frame, args.frame}},
       {"hidden", args.hidden},
       {"layers", args.layers},
       {"action_dim", args.action_dim},
       {"architecture", config.architecture},
       {"unit", unit},
       {"updates_per_s", median},
       {"ms_per_update", 1000.0 / median},
       {"updates", rates},
       {"threads", ThreadsJson()}});
  std::ostringstream summary;
  summary << algo << ": " << Fixed(median, 2) << " updates/s, " << Fixed(1000.0 / median, 2)
          << " ms/update (median of " << rates.size() << " repeats of " << args.updates << "); "
          << "batch " << b << " of " << args.channels << " x " << args.frame << " x " << args.frame
          << " frames, " << args.layers << " x " << args.hidden << ", action " << args.action_dim
          << "\n";
  result.summary = summary.str();
  return result;
}

}  // namespace

AgentBenchResult BenchSacAeUpdates(const std::string& algo, const AgentBenchSizes& args) {
  return TimePixelUpdates<agents::SacAeLearner, agents::SacAeConfig>(
      algo, args,
      "one update (SAC on the encoder's features, one autoencoder step; actor and targets every "
      "2nd update, as the config's defaults)");
}

AgentBenchResult BenchDeepMdpUpdates(const std::string& algo, const AgentBenchSizes& args) {
  return TimePixelUpdates<agents::DeepMdpLearner, agents::DeepMdpConfig>(
      algo, args,
      "one update (SAC on the encoder's features, transition and reward step, decoder step; "
      "actor and targets every 2nd update)");
}

AgentBenchResult BenchHipBmdpUpdates(const std::string& algo, const AgentBenchSizes& args) {
  return TimePixelUpdates<agents::HipBmdpLearner, agents::HipBmdpConfig>(
      algo, args,
      "one update (DeepMDP's with the task parameters, the contrastive step; actor and targets "
      "every 2nd update)");
}

}  // namespace manyworlds::experiments
