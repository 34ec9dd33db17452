// The configuration of a training run (`manyworlds train CONFIG.yaml`).
//
// YAML schema (every key optional; unknown keys are errors):
//
//   env:
//     id: point-nav        # one registry id whose task sampler gives the tasks, or
//     tasks: [reach, push] # a list of registry ids, one task each (not both)
//     num_tasks: 0         # with id: 0 = the env's own task list if it has one
//                          # (benchmarks: mt10's 10 tasks, each with its
//                          # variations), else one sampled task; n >= 1 = n
//                          # tasks sampled with task_seed
//     variations_per_task: 0  # benchmark variations used per task (0 = all;
//                          # 1 = MTRL's one fixed goal per task); for an env
//                          # without a task list, n >= 1 task states sampled
//                          # per task (a meta-RL task distribution; 0 = 1)
//     task_states: []      # optional explicit task states ({env, params} each),
//                          # one per task, instead of sampling them
//     options: {}          # registry options for every env (e.g. horizon,
//                          # max_episode_steps)
//     envs_per_task: 1     # training envs stepped per task
//     task_seed: 0         # draws the task set; independent of experiment.seed
//     support_variations: 0  # the support/query split (both 0: none): each
//     query_variations: 0    # task's variations are groups (layouts) of
//                          # support + query; meta-learners (maml, rl2,
//                          # pearl) adapt on a group's support variations and
//                          # train and are scored on its query ones
//   eval_env: null         # held-out meta-test tasks: keys of env (id, tasks,
//                          # num_tasks, variations_per_task, task_states,
//                          # options, task_seed, support_variations,
//                          # query_variations) replacing the env section's,
//                          # e.g. {options: {split: test}} for ML1/ML10's test
//                          # split; when set, every evaluation also runs the
//                          # meta-test protocol on them (meta_test.jsonl)
//   meta_test:             # the meta-test protocol (experiments/evaluation/meta_test_protocol.h)
//     protocol: metalearning_evaluation  # Meta-World v3's (its names and
//                          # defaults below), or per_variation
//     num_evals: 10        # rounds, each on newly sampled goals
//     adaptation_steps: 1  # adaptation phases per round, each ending in Actor::Adapt
//     adaptation_episodes: 10  # per env and adaptation phase, sampled
//     evaluation_episodes: 3   # per task (per_variation: per trial), after adaptation
//     meta_batch_size: 20  # envs, split evenly between the held-out tasks
//     total_tasks_per_cls: 0  # goals per held-out task: its first N variations (0: all)
//     task_select: random  # an env's goal each round: random | pseudorandom
//     terminate_on_success: true  # evaluation episodes end at the first success
//     exploration_episodes: 10  # per_variation: per trial, sampled, before Actor::Adapt
//     trials_per_task: 10       # per_variation: variations tried per held-out task
//     sample_evaluation: false  # evaluation episodes sample instead of the mode
//   agent:
//     algo: sac            # the algorithm: a row of the registry
//                          # (experiments/algorithms.cc; `manyworlds train --help`
//                          # lists them); the other keys are that algorithm's
//                          # config (agents/<algo>/<algo>_config.h), e.g.
//                          # hidden_dim, actor_lr, architecture, pcgrad;
//                          # agent.seed is mixed with experiment.seed
//   replay:                # off-policy algorithms (sac, pearl) only
//     capacity: 1000000    # transitions, split evenly per task (pearl: per task
//                          # variation, in each of its RL and encoder buffers)
//     sampling: balanced   # balanced | uniform
//   experiment:
//     seed: 1
//     steps_per_task: 100000   # env steps per training env
//     warmup_steps: 1500       # off-policy: uniform random actions first (per env);
//                              # pearl: collection with prior z only, no updates
//     updates_per_step: 1.0    # off-policy: gradient updates per loop step (all envs)
//     batch_size: 0            # off-policy: transitions per update; 0 = agent.batch_size x
//                              # num_tasks
//     eval_every: 10000        # env steps per task; 0 = only at the end
//     eval_episodes: 10        # per task (Meta-World v3's evaluation: 50)
//     eval_terminate_on_success: false  # evaluation episodes end at the first
//                              # success (v3's evaluation; the Meta-World configs set it)
//     num_threads: 1           # executor worker threads
//     checkpoint_every: 50000  # env steps per task; 0 = only at the end
//     keep_checkpoints: 1      # newest checkpoints kept (0 = all)
//     run_dir: runs/train
//     init_from: ""            # a checkpoint directory (or a run: its newest
//                              # intact one) whose learner a new run starts from
//                              # (fine-tuning), verified as resume verifies; same
//                              # algorithm and network sizes; "" = fresh networks
//
// Only the keys of the chosen algorithm are allowed under agent:, and a
// config whose replay or off-policy experiment keys differ from their
// defaults is refused for an on-policy algorithm (they would be ignored).
//
// Training runs in rounds of one episode length (the largest
// max_episode_steps of the envs): every env starts a fresh episode at the
// start of a round (MTRL resets its Meta-World envs every episode length).
// Evaluations and checkpoints happen at round boundaries, the first one at or
// after each multiple of eval_every / checkpoint_every, and after the last
// round.
#ifndef MANYWORLDS_EXPERIMENTS_TRAIN_CONFIG_H_
#define MANYWORLDS_EXPERIMENTS_TRAIN_CONFIG_H_

#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "manyworlds/core/error.h"
#include "manyworlds/core/visit_fields.h"
#include "manyworlds/experiments/agent_config.h"
#include "manyworlds/experiments/task_set.h"

namespace manyworlds::experiments {


struct ReplaySectionConfig {
  int64_t capacity = 1000000;
  std::string sampling = "balanced";
};

struct ExperimentSectionConfig {
  uint64_t seed = 1;
  int64_t steps_per_task = 100000;
  int64_t warmup_steps = 1500;
  double updates_per_step = 1.0;
  int64_t batch_size = 0;
  int64_t eval_every = 10000;
  int64_t eval_episodes = 10;
  bool eval_terminate_on_success = false;
  int num_threads = 1;
  int64_t checkpoint_every = 50000;
  int64_t keep_checkpoints = 1;
  std::string run_dir = "runs/train";
  // checkpoint directory (or a run: its newest intact checkpoint) to start a new run from
  std::string init_from;  // ("" none)
};

// The meta-test protocol's settings. Defaults: Meta-World v3's
// metalearning_evaluation (10 adaptation episodes, 3 evaluation episodes);
// garage's MetaEvaluator uses 10 and 1.
inline constexpr char kMetalearningEvaluation[] = "metalearning_evaluation";
inline constexpr char kPerVariation[] = "per_variation";

struct MetaTestConfig {
  std::string protocol = kMetalearningEvaluation;
  // metalearning_evaluation: Meta-World v3's parameters, names and defaults
  int64_t num_evals = 10;
  int64_t adaptation_steps = 1;
  int64_t adaptation_episodes = 10;
  int64_t meta_batch_size = 20;
  int64_t total_tasks_per_cls = 0;  // goals per held-out task: its first N variations (0: all)
  std::string task_select = "random";
  bool terminate_on_success = true;
  // both protocols: per task (metalearning_evaluation) or per trial (per_variation)
  int64_t evaluation_episodes = 3;
  // per_variation
  int64_t exploration_episodes = 10;
  int64_t trials_per_task = 10;
  bool sample_evaluation = false;

  template <class F>
  void VisitFields(F&& f) {
    MANYWORLDS_VISIT_FIELDS(f, protocol, num_evals, adaptation_steps, adaptation_episodes,
                            evaluation_episodes, meta_batch_size, total_tasks_per_cls, task_select,
                            terminate_on_success, exploration_episodes, trials_per_task,
                            sample_evaluation);
  }
  bool per_variation() const { return protocol == kPerVariation; }
  // The protocol a key belongs to (kMetalearningEvaluation or kPerVariation),
  // or "" for a key both protocols use: the one list of which is whose.
  static std::string_view ProtocolOf(std::string_view key) {
    for (std::string_view k : {"num_evals", "adaptation_steps", "adaptation_episodes",
                               "meta_batch_size", "total_tasks_per_cls", "task_select",
                               "terminate_on_success"}) {
      if (k == key) return kMetalearningEvaluation;
    }
    if (key == "exploration_episodes" || key == "trials_per_task") return kPerVariation;
    return {};
  }
  // Throws ConfigError naming the field (prefix "meta_test.").
  void Validate() const;
};

struct TrainConfig {
  EnvSectionConfig env;
  std::optional<EnvSectionConfig> eval_env;  // held-out tasks of the meta-test
  MetaTestConfig meta_test;
  AgentConfig agent;
  ReplaySectionConfig replay;
  ExperimentSectionConfig experiment;

  // Defaults, then the file (if any), then Hydra-style dotted overrides
  // ("experiment.seed=3", "agent.hidden_dim=64"). Throws ConfigError for a
  // syntax error, an unknown key or an ill-typed value; does not Validate.
  static TrainConfig Load(const std::optional<std::filesystem::path>& file,
                          const std::vector<std::string>& overrides = {});
  static TrainConfig FromJson(const nlohmann::json& json);
  // The full resolved tree (every key, defaults included).
  nlohmann::json ToJson() const;

  // Throws ConfigError naming the first bad field and what is allowed
  // (including the agent section). Env ids are checked when the envs are made.
  void Validate() const;

  // Off-policy: transitions per update for num_tasks tasks.
  int64_t TotalBatchSize(int64_t num_tasks) const;
};

}  // namespace manyworlds::experiments

#endif  // MANYWORLDS_EXPERIMENTS_TRAIN_CONFIG_H_
