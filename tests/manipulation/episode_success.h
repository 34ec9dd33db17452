// Shared by the manipulation task tests: how many of `variations`
// consecutive task variations (task seed `task_seed`) a policy solves, i.e.
// reaches info success at some step of a 500-step episode.
#ifndef MANYWORLDS_TESTS_MANIPULATION_EPISODE_SUCCESS_H_
#define MANYWORLDS_TESTS_MANIPULATION_EPISODE_SUCCESS_H_

#include <cstdint>
#include <vector>

#include "manyworlds/core/env.h"
#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/sawyer_task.h"

namespace manyworlds::manipulation {

// mean_steps (optional): the mean number of steps to the first success.
inline int CountSuccesses(Env& env, Policy& policy, int variations, uint64_t task_seed,
                          double* mean_steps = nullptr) {
  env.SeedTask(task_seed);
  int successes = 0;
  long success_steps = 0;
  std::vector<float> action(4);
  for (int variation = 0; variation < variations; ++variation) {
    env.ResetTaskState();
    Observation obs = env.Reset();
    policy.BeginEpisode();
    for (int t = 0; t < kMaxEpisodeSteps; ++t) {
      policy.Act(obs.env_obs, obs.task_obs, action);
      StepResult r = env.Step(action);
      if (r.info.Get("success") > 0) {
        ++successes;
        success_steps += t + 1;
        break;
      }
      obs = r.obs;
    }
  }
  if (mean_steps != nullptr) *mean_steps = successes ? double(success_steps) / successes : 0.0;
  return successes;
}

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_TESTS_MANIPULATION_EPISODE_SUCCESS_H_
