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
//                          # 1 = MTRL's one fixed goal per task)
//     task_states: []      # optional explicit task states ({env, params} each),
//                          # one per task, instead of sampling them
//     options: {}          # registry options for every env (e.g. horizon,
//                          # max_episode_steps)
//     envs_per_task: 1     # training envs stepped per task
//     task_seed: 0         # draws the task set; independent of experiment.seed
//   agent: {...}           # SacConfig, same field names (hidden_dim, actor_lr, ...,
//                          # architecture, pcgrad...); agent.batch_size is per
//                          # task; agent.seed is mixed with experiment.seed
//   replay:
//     capacity: 1000000    # transitions, split evenly per task
//     sampling: balanced   # balanced | uniform
//   experiment:
//     seed: 1
//     steps_per_task: 100000   # env steps per training env
//     warmup_steps: 1500       # uniform random actions first (per env)
//     updates_per_step: 1.0    # gradient updates per loop step (all envs), may be < 1
//     batch_size: 0            # transitions per update; 0 = agent.batch_size x num_tasks
//     eval_every: 10000        # env steps per task; 0 = only at the end
//     eval_episodes: 10        # per task
//     num_threads: 1           # executor worker threads
//     checkpoint_every: 50000  # env steps per task; 0 = only at the end
//     keep_checkpoints: 1      # newest checkpoints kept (0 = all)
//     run_dir: runs/train
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
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "manyworlds/agents/replay_buffer.h"
#include "manyworlds/agents/sac_config.h"

namespace manyworlds::experiments {

struct EnvSectionConfig {
  std::string id;                  // one env id (tasks empty), or
  std::vector<std::string> tasks;  // one env id per task
  int64_t num_tasks = 0;           // with id; 0 = the env's task groups, or 1
  int64_t variations_per_task = 0; // 0 = all of a group's states
  nlohmann::json task_states = nlohmann::json::array();  // explicit, one per task
  nlohmann::json options = nlohmann::json::object();     // registry options
  int64_t envs_per_task = 1;
  uint64_t task_seed = 0;
};

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
  int num_threads = 1;
  int64_t checkpoint_every = 50000;
  int64_t keep_checkpoints = 1;
  std::string run_dir = "runs/train";
};

struct TrainConfig {
  EnvSectionConfig env;
  agents::SacConfig agent;
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

  agents::ReplaySampling sampling() const;
  // Transitions per update for num_tasks tasks.
  int64_t TotalBatchSize(int64_t num_tasks) const;
};

}  // namespace manyworlds::experiments

#endif  // MANYWORLDS_EXPERIMENTS_TRAIN_CONFIG_H_
