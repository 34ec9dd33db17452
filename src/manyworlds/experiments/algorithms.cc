#include "manyworlds/experiments/algorithms.h"

#include <memory>
#include <utility>

#include "manyworlds/agents/deepmdp/deepmdp.h"
#include "manyworlds/agents/distral/distral.h"
#include "manyworlds/agents/hipbmdp/hipbmdp.h"
#include "manyworlds/agents/maml/maml.h"
#include "manyworlds/agents/pearl/pearl_config.h"
#include "manyworlds/agents/ppo/ppo.h"
#include "manyworlds/agents/rl2/rl2.h"
#include "manyworlds/agents/sac/sac_config.h"
#include "manyworlds/agents/sac_ae/sac_ae.h"
#include "manyworlds/agents/te_ppo/te_ppo.h"
#include "manyworlds/agents/trpo/trpo.h"
#include "manyworlds/config/reader.h"
#include "manyworlds/core/error.h"
#include "manyworlds/core/registry.h"
#include "manyworlds/experiments/algorithm.h"
#include "manyworlds/experiments/loops/loops.h"
#include "manyworlds/nn/device.h"

namespace manyworlds::experiments {
namespace {

template <class Config>
std::unique_ptr<AgentParams> Defaults() {
  return std::make_unique<TypedAgentParams<Config>>();
}

// A registry row for config type Config.
template <class Config>
AlgorithmInfo Row(std::string name, AlgorithmFamily family, bool discrete_actions, bool box_actions,
                  std::string description, AlgorithmFactory make, AgentBench bench,
                  ObservationKind observations = ObservationKind::kState) {
  return {std::move(name),
          family,
          discrete_actions,
          box_actions,
          std::move(description),
          &Defaults<Config>,
          make,
          bench,
          observations};
}

// Whether an algorithm acts on pixel frames (pixels) or on the state.
bool ActsOn(const AlgorithmInfo& info, bool pixels) {
  return info.observations == ObservationKind::kStateOrPixels ||
         (info.observations == ObservationKind::kPixels) == pixels;
}

// The registered names of the algorithms that act on frames (pixels) or on the state.
std::string NamesFor(bool pixels) {
  std::string names;
  for (const AlgorithmInfo& a : Algorithms()) {
    if (ActsOn(a, pixels)) names += (names.empty() ? "" : ", ") + a.name;
  }
  return names;
}

constexpr const char* kDefaultAlgorithm = "sac";

}  // namespace

AgentConfig::AgentConfig() : AgentConfig(DefaultAgentConfig(kDefaultAlgorithm)) {}

const std::vector<AlgorithmInfo>& Algorithms() {
  // Documentation order.
  using F = AlgorithmFamily;
  static const std::vector<AlgorithmInfo> list = {
      Row<agents::SacConfig>(
          "sac", F::kOffPolicy, false, true,
          "soft actor-critic and its multi-task variants (MT-SAC, multi-head, task encoder, "
          "CARE mixture of encoders, PCGrad); on obs=pixels envs with MTRL's convolutional "
          "encoder trained by the critic",
          &MakeSacAlgorithm, &BenchSacUpdates, ObservationKind::kStateOrPixels),
      Row<agents::PpoConfig>("ppo", F::kOnPolicy, true, true,
                             "proximal policy optimisation (MT-PPO with several tasks)",
                             &MakeOnPolicy<agents::PpoLearner, agents::PpoConfig>,
                             &BenchPpoUpdates),
      Row<agents::TrpoConfig>("trpo", F::kOnPolicy, true, true,
                              "trust region policy optimisation (MT-TRPO with several tasks)",
                              &MakeOnPolicy<agents::TrpoLearner, agents::TrpoConfig>,
                              &BenchTrpoUpdates),
      Row<agents::TePpoConfig>(
          "te_ppo", F::kOnPolicy, true, true,
          "PPO with learned task embeddings (encoder, inference network; garage's TEPPO)",
          &MakeOnPolicy<agents::TePpoLearner, agents::TePpoConfig>, &BenchTePpoUpdates),
      Row<agents::Rl2Config>(
          "rl2", F::kOnPolicy, true, true,
          "RL2 meta-RL: a GRU policy trained with PPO over trials of several episodes of one "
          "task (garage's RL2PPO)",
          &MakeOnPolicy<agents::Rl2Learner, agents::Rl2Config>, &BenchRl2Updates),
      Row<agents::MamlConfig>(
          "maml", F::kOnPolicy, true, true,
          "MAML-TRPO meta-RL: one inner policy-gradient step per task instance, TRPO outer "
          "step through it (garage's MAMLTRPO)",
          &MakeOnPolicy<agents::MamlLearner, agents::MamlConfig>, &BenchMamlUpdates),
      Row<agents::PearlConfig>(
          "pearl", F::kOffPolicy, false, true,
          "PEARL meta-RL: SAC conditioned on a latent task variable inferred by a context "
          "encoder (product of Gaussians), per-task replay (oyster's PEARL)",
          &MakePearlAlgorithm, &BenchPearlUpdates),
      Row<agents::DistralConfig>(
          "distral", F::kOffPolicy, false, true,
          "Distral: one SAC agent per task regularised towards a distilled central policy "
          "(KL weight distral_alpha, entropy weight the learned temperature; Teh et al. 2017, "
          "MTRL's distral)",
          &MakeDistralAlgorithm, &BenchDistralUpdates),
      Row<agents::SacAeConfig>(
          "sac_ae", F::kOffPolicy, false, true,
          "SAC-AE: SAC on pixel frames whose convolutional encoder a deconvolutional decoder's "
          "reconstruction loss also trains (Yarats et al. 2019, MTRL's sac_ae); multi-task as "
          "sac's architectures",
          &MakeSacAeAlgorithm, &BenchSacAeUpdates,
          ObservationKind::kPixels),
      Row<agents::DeepMdpConfig>(
          "deepmdp", F::kOffPolicy, false, true,
          "DeepMDP: SAC-AE whose latent also trains a latent transition and reward model, the "
          "decoder drawing the next frame (Gelada et al. 2019, MTRL's deepmdp)",
          &MakeDeepMdpAlgorithm, &BenchDeepMdpUpdates,
          ObservationKind::kPixels),
      Row<agents::HipBmdpConfig>(
          "hipbmdp", F::kOffPolicy, false, true,
          "HiP-BMDP: DeepMDP with a learned hidden parameter per task in the latent, trained by "
          "the model losses and a contrastive loss (Zhang et al. 2021, MTRL's hipbmdp)",
          &MakeHipBmdpAlgorithm, &BenchHipBmdpUpdates,
          ObservationKind::kPixels),
  };
  return list;
}

std::string AlgorithmNames() {
  std::string names;
  for (const AlgorithmInfo& a : Algorithms()) names += (names.empty() ? "" : ", ") + a.name;
  return names;
}

const AlgorithmInfo* LookupAlgorithm(const std::string& name) {
  for (const AlgorithmInfo& a : Algorithms()) {
    if (a.name == name) return &a;
  }
  return nullptr;
}

std::string UnknownAlgorithm(const std::string& key, const std::string& name) {
  std::vector<std::string> names;
  for (const AlgorithmInfo& a : Algorithms()) names.push_back(a.name);
  return key + ": unknown algorithm '" + ShortenForMessage(name) + "'" +
         SuggestNearest(name, names) + "; allowed: " + AlgorithmNames();
}

const AlgorithmInfo& FindAlgorithm(const std::string& name) {
  if (const AlgorithmInfo* info = LookupAlgorithm(name)) return *info;
  throw ConfigError(UnknownAlgorithm("'agent.algo'", name));
}

const char* FamilyName(AlgorithmFamily family) {
  return family == AlgorithmFamily::kOffPolicy ? "off-policy" : "on-policy";
}

AgentConfig DefaultAgentConfig(const std::string& algo) {
  const AlgorithmInfo& info = FindAlgorithm(algo);
  return AgentConfig(info.name, info.default_config());
}

AgentConfig ReadAgentConfig(const nlohmann::json& section) {
  ConfigReader r(section, "agent");
  std::string algo = kDefaultAlgorithm;
  r.Read("algo", algo);
  AgentConfig agent = DefaultAgentConfig(algo);
  std::string device = agent.device();
  r.Read("device", device);
  agent.set_device(device);
  agent.params().Read(r);
  r.Finish();
  return agent;
}

nlohmann::json AgentConfigToJson(const AgentConfig& agent) {
  nlohmann::json j = agent.params().ToJson();
  j["algo"] = agent.algo();
  j["device"] = agent.device();
  return j;
}

void ValidateAgentConfig(const AgentConfig& agent) {
  nn::ParseDevice(agent.device(), "agent.device");
  agent.params().Validate();
}

std::unique_ptr<Algorithm> MakeAlgorithm(const AlgorithmSetup& setup) {
  return FindAlgorithm(setup.config.agent.algo()).make(setup);
}

std::unique_ptr<Algorithm> BuildAlgorithm(const TrainConfig& config, const TaskSet& tasks,
                                          const EnvFacts& facts) {
  nn::ResolveDevice(config.agent.device(), "agent.device");  // "cpu", or why not a GPU
  CheckAlgorithmEnvs(config.agent, facts, tasks);
  AlgorithmSetup setup{config,
                       facts,
                       tasks,
                       tasks.size(),
                       tasks.size() * config.env.envs_per_task,
                       facts.episode_length};
  std::unique_ptr<Algorithm> algorithm = MakeAlgorithm(setup);
  if (tasks.has_split() && !algorithm->SupportsSplit()) {
    throw ConfigError("'env.support_variations': agent.algo '" + config.agent.algo() +
                      "' cannot train on a support/query split; it needs a meta-learner whose "
                      "trials have support and query rounds (maml, rl2 with episodes_per_trial "
                      ">= 2, pearl with prior_episodes >= 1 and later rounds)");
  }
  return algorithm;
}

void CheckAlgorithmEnvs(const AgentConfig& agent, const EnvFacts& facts, const TaskSet& tasks) {
  const AlgorithmInfo& info = FindAlgorithm(agent.algo());
  const bool discrete = facts.num_actions > 0;
  if ((discrete && !info.discrete_actions) || (!discrete && !info.box_actions)) {
    throw ConfigError("agent.algo '" + info.name + "' needs a " +
                      (discrete ? std::string("Box") : std::string("Discrete")) +
                      " action space, but env '" + tasks.tasks.front().env_id + "' has " +
                      (discrete ? "Discrete(" + std::to_string(facts.num_actions) + ")"
                                : std::string("a Box")) +
                      " actions; algorithms for " + (discrete ? "Discrete" : "Box") +
                      " actions: " + [&] {
                        std::string names;
                        for (const AlgorithmInfo& a : Algorithms()) {
                          if (discrete ? a.discrete_actions : a.box_actions) {
                            names += (names.empty() ? "" : ", ") + a.name;
                          }
                        }
                        return names;
                      }());
  }
  const bool pixels = !facts.pixel_shape.empty();
  if (!ActsOn(info, pixels)) {
    throw ConfigError(
        "agent.algo '" + info.name + "' learns from " + (pixels ? "the state" : "pixel frames") +
        ", but env '" + tasks.tasks.front().env_id + "' " +
        (pixels ? "has obs=pixels: drop env.options.obs, or use an algorithm for pixels: "
                : "has no pixel observations: set env.options.obs=pixels, or use an algorithm "
                  "for the state: ") +
        NamesFor(pixels));
  }
}

}  // namespace manyworlds::experiments
