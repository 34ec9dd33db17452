#include "manyworlds/experiments/algorithms.h"

#include <utility>
#include <variant>

#include "manyworlds/config/reader.h"
#include "manyworlds/core/error.h"
#include "manyworlds/core/registry.h"

namespace manyworlds::experiments {
namespace {

// The default-constructed alternative `index` of AgentConfig::params (the
// registry's order is the variant's order).
template <size_t... I>
void EmplaceDefault(decltype(AgentConfig::params)& params, size_t index,
                    std::index_sequence<I...>) {
  ((index == I ? (void)params.emplace<I>() : void()), ...);
}

void ReadSac(ConfigReader& r, agents::SacConfig& c) {
  r.Read("hidden_dim", c.hidden_dim);
  r.Read("num_layers", c.num_layers);
  r.Read("actor_lr", c.actor_lr);
  r.Read("critic_lr", c.critic_lr);
  r.Read("alpha_lr", c.alpha_lr);
  r.Read("adam_beta1", c.adam_beta1);
  r.Read("adam_beta2", c.adam_beta2);
  r.Read("discount", c.discount);
  r.Read("tau", c.tau);
  r.Read("init_temperature", c.init_temperature);
  r.Read("batch_size", c.batch_size);
  if (r.Has("target_entropy")) {
    nlohmann::json value;
    r.Read("target_entropy", value);
    if (value.is_null()) {
      c.target_entropy.reset();
    } else if (value.is_number()) {
      c.target_entropy = value.get<double>();
    } else {
      throw ConfigError("'" + r.FullKey("target_entropy") +
                        "' must be a number or null (= -action_dim), got " + value.dump());
    }
  }
  r.Read("disentangled_alpha", c.disentangled_alpha);
  r.Read("log_std_min", c.log_std_min);
  r.Read("log_std_max", c.log_std_max);
  r.Read("actor_update_freq", c.actor_update_freq);
  r.Read("critic_target_update_freq", c.critic_target_update_freq);
  r.Read("max_critic_loss", c.max_critic_loss);
  r.Read("seed", c.seed);
  r.Read("architecture", c.architecture);
  r.Read("task_embedding_dim", c.task_embedding_dim);
  r.Read("num_experts", c.num_experts);
  r.Read("encoder_dim", c.encoder_dim);
  r.Read("pcgrad", c.pcgrad);
  r.Read("update_shards", c.update_shards);
  r.Read("update_threads", c.update_threads);
}

nlohmann::json SacToJson(const agents::SacConfig& c) {
  return {
      {"hidden_dim", c.hidden_dim},
      {"num_layers", c.num_layers},
      {"actor_lr", c.actor_lr},
      {"critic_lr", c.critic_lr},
      {"alpha_lr", c.alpha_lr},
      {"adam_beta1", c.adam_beta1},
      {"adam_beta2", c.adam_beta2},
      {"discount", c.discount},
      {"tau", c.tau},
      {"init_temperature", c.init_temperature},
      {"batch_size", c.batch_size},
      {"target_entropy",
       c.target_entropy ? nlohmann::json(*c.target_entropy) : nlohmann::json(nullptr)},
      {"disentangled_alpha", c.disentangled_alpha},
      {"log_std_min", c.log_std_min},
      {"log_std_max", c.log_std_max},
      {"actor_update_freq", c.actor_update_freq},
      {"critic_target_update_freq", c.critic_target_update_freq},
      {"max_critic_loss", c.max_critic_loss},
      {"seed", c.seed},
      {"architecture", c.architecture},
      {"task_embedding_dim", c.task_embedding_dim},
      {"num_experts", c.num_experts},
      {"encoder_dim", c.encoder_dim},
      {"pcgrad", c.pcgrad},
      {"update_shards", c.update_shards},
      {"update_threads", c.update_threads},
  };
}

// Configs with VisitFields (the policy-gradient family).
template <class C>
void ReadFields(ConfigReader& r, C& c) {
  c.VisitFields([&](const char* key, auto& field) { r.Read(key, field); });
}

template <class C>
nlohmann::json FieldsToJson(C c) {
  nlohmann::json j = nlohmann::json::object();
  c.VisitFields([&](const char* key, const auto& field) { j[key] = field; });
  return j;
}

}  // namespace

std::string AgentConfig::algo() const { return Algorithms().at(params.index()).name; }

const std::vector<AlgorithmInfo>& Algorithms() {
  // Order = AgentConfig::params' alternatives.
  static const std::vector<AlgorithmInfo> list = {
      {"sac", AlgorithmFamily::kOffPolicy, false, true,
       "soft actor-critic and its multi-task variants (MT-SAC, multi-head, task encoder, "
       "CARE mixture of encoders, PCGrad)"},
      {"ppo", AlgorithmFamily::kOnPolicy, true, true,
       "proximal policy optimisation (MT-PPO with several tasks)"},
      {"trpo", AlgorithmFamily::kOnPolicy, true, true,
       "trust region policy optimisation (MT-TRPO with several tasks)"},
      {"te_ppo", AlgorithmFamily::kOnPolicy, true, true,
       "PPO with learned task embeddings (encoder, inference network; garage's TEPPO)"},
      {"rl2", AlgorithmFamily::kOnPolicy, true, true,
       "RL2 meta-RL: a GRU policy trained with PPO over trials of several episodes of one task "
       "(garage's RL2PPO)"},
      {"maml", AlgorithmFamily::kOnPolicy, true, true,
       "MAML-TRPO meta-RL: one inner policy-gradient step per task instance, TRPO outer step "
       "through it (garage's MAMLTRPO)"},
      {"pearl", AlgorithmFamily::kOffPolicy, false, true,
       "PEARL meta-RL: SAC conditioned on a latent task variable inferred by a context "
       "encoder (product of Gaussians), per-task replay (oyster's PEARL)"},
  };
  return list;
}

std::string AlgorithmNames() {
  std::string names;
  for (const AlgorithmInfo& a : Algorithms()) names += (names.empty() ? "" : ", ") + a.name;
  return names;
}

const AlgorithmInfo& FindAlgorithm(const std::string& name) {
  std::vector<std::string> names;
  for (const AlgorithmInfo& a : Algorithms()) {
    if (a.name == name) return a;
    names.push_back(a.name);
  }
  throw ConfigError("'agent.algo': unknown algorithm '" + name + "'" +
                    SuggestNearest(name, names) + "; allowed: " + AlgorithmNames());
}

const char* FamilyName(AlgorithmFamily family) {
  return family == AlgorithmFamily::kOffPolicy ? "off-policy" : "on-policy";
}

AgentConfig DefaultAgentConfig(const std::string& algo) {
  const AlgorithmInfo& info = FindAlgorithm(algo);
  const size_t index = static_cast<size_t>(&info - Algorithms().data());
  AgentConfig agent;
  using Params = decltype(AgentConfig::params);
  static_assert(std::variant_size_v<Params> > 0);
  EmplaceDefault(agent.params, index, std::make_index_sequence<std::variant_size_v<Params>>());
  return agent;
}

AgentConfig ReadAgentConfig(const nlohmann::json& section) {
  ConfigReader r(section, "agent");
  std::string algo = "sac";
  r.Read("algo", algo);
  AgentConfig agent = DefaultAgentConfig(algo);
  std::visit(
      [&](auto& c) {
        using C = std::decay_t<decltype(c)>;
        if constexpr (std::is_same_v<C, agents::SacConfig>) {
          ReadSac(r, c);
        } else {
          ReadFields(r, c);
        }
      },
      agent.params);
  r.Finish();
  return agent;
}

nlohmann::json AgentConfigToJson(const AgentConfig& agent) {
  nlohmann::json j = std::visit(
      [](const auto& c) -> nlohmann::json {
        using C = std::decay_t<decltype(c)>;
        if constexpr (std::is_same_v<C, agents::SacConfig>) {
          return SacToJson(c);
        } else {
          return FieldsToJson(c);
        }
      },
      agent.params);
  j["algo"] = agent.algo();
  return j;
}

void ValidateAgentConfig(const AgentConfig& agent) {
  std::visit([](const auto& c) { c.Validate(); }, agent.params);
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
}

}  // namespace manyworlds::experiments
