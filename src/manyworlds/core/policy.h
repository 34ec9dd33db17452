// Policies that drive an env from its observation, and the rollout loop.
#ifndef MANYWORLDS_CORE_POLICY_H_
#define MANYWORLDS_CORE_POLICY_H_

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "manyworlds/core/env.h"
#include "manyworlds/core/rng.h"

namespace manyworlds {

class Policy {
 public:
  virtual ~Policy() = default;
  // Called at the start of every episode.
  virtual void BeginEpisode() {}
  // Writes an action (action_space.flat_size() floats) for the observation.
  virtual void Act(std::span<const float> env_obs, std::span<const float> task_obs,
                   std::span<float> action) = 0;
};

// A capability of envs that have a scripted (expert) policy: the manipulation
// tasks and benchmarks, the box world. Found behind wrappers with
// FindThroughWrappers<ScriptedPolicySource>(env).
class ScriptedPolicySource {
 public:
  virtual ~ScriptedPolicySource() = default;
  // A new scripted policy acting in this env; the env must outlive it.
  virtual std::unique_ptr<Policy> CreateScriptedPolicy() const = 0;
};

// Uniform samples from the action space, from its own seeded generator.
class RandomPolicy : public Policy {
 public:
  RandomPolicy(Space action_space, uint64_t seed) : space_(std::move(action_space)), rng_(seed) {}
  void Act(std::span<const float>, std::span<const float>, std::span<float> action) override {
    space_.Sample(rng_, action);
  }

 private:
  Space space_;
  Rng rng_;
};

struct EpisodeStats {
  double episode_return = 0.0;
  int64_t length = 0;
  // 1 if the env reported info "success" > 0 at any step; -1 if the env
  // does not report success.
  int success = -1;
  bool terminated = false;
  bool truncated = false;
};

struct RolloutSummary {
  std::vector<EpisodeStats> episodes;
  double mean_return = 0.0;
  double mean_length = 0.0;
  // Fraction of successful episodes; negative if the env reports no success.
  double success_rate = -1.0;

  // {"episodes": [{"return", "length", "success"}], "mean_return",
  //  "success_rate"} (success / success_rate are null without a success field).
  nlohmann::json ToJson() const;
};

// Runs `episodes` episodes: Reset, then Step with the policy's actions until
// terminated or truncated. Episodes without a time limit are cut after
// `max_steps_per_episode` steps (counted as truncated).
RolloutSummary Rollout(Env& env, Policy& policy, int episodes,
                       int64_t max_steps_per_episode = 100000);

// Independent episodes, in parallel: episode i is set up by prepare(env, i)
// (seeds, task state; it returns the episode's policy) and run once to its
// end. The calling thread steps `env`; each of the other num_threads - 1
// threads steps its own env from make_env (same id and options). Because
// every episode is set up from its index alone, the stats (in episode order)
// do not depend on num_threads. The first error of any episode is rethrown
// after all threads stopped. Throws ConfigError on num_episodes < 0 or
// num_threads < 1.
using EnvMaker = std::function<std::unique_ptr<Env>()>;
using EpisodeSetup = std::function<std::unique_ptr<Policy>(Env& env, int episode)>;
std::vector<EpisodeStats> RunEpisodes(Env& env, const EnvMaker& make_env, int num_episodes,
                                      int num_threads, const EpisodeSetup& prepare,
                                      int64_t max_steps_per_episode = 100000);

// Mean return, length and success rate of a list of episodes (success rate
// negative when the env reports no success).
RolloutSummary Summarize(std::vector<EpisodeStats> episodes);

// Rollouts of one group of task states (e.g. one benchmark task).
struct GroupRollout {
  std::string name;
  RolloutSummary summary;
};

// For each group, one episode on each of its first `per_group` task states
// (all of them if per_group <= 0), in order: SetTaskState, then Rollout.
std::vector<GroupRollout> RolloutTaskGroups(Env& env, Policy& policy,
                                            const std::vector<TaskGroup>& groups, int per_group);

// All episodes of the groups as one summary, with "per_task" added to its
// JSON: [{"task", "episodes", "mean_return", "success_rate"}] in group order.
RolloutSummary MergeGroups(const std::vector<GroupRollout>& groups);
nlohmann::json GroupsToJson(const std::vector<GroupRollout>& groups);

}  // namespace manyworlds

#endif  // MANYWORLDS_CORE_POLICY_H_
