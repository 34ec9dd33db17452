// Classical strategies for the `tabular-mdp` env's task distribution, the
// yardsticks an RL2 tabular-MDP result is read against (the RL2 paper
// compares with random, greedy, epsilon-greedy and posterior sampling,
// among others). A trial is `episodes` episodes of `horizon` steps on one
// MDP; every episode starts in state 0, rewards are Bernoulli(R[s, a]) and
// the next state is drawn from P[s, a, :], exactly as the env does. The
// score is the trial's total reward.
//
//   random          a uniformly random action every step;
//   greedy          certainty equivalence: plan the rest of the episode on
//                   the posterior-mean MDP (Beta(1, 1) rewards, Dirichlet(1)
//                   transitions), replanned after every step; ties go to the
//                   less-tried action, then the lower index;
//   epsilon-greedy  greedy, but a uniformly random action with probability
//                   0.1;
//   psrl            posterior sampling (Osband, Russo and Van Roy 2013): one
//                   MDP drawn from the posterior at the start of each
//                   episode, its optimal finite-horizon policy followed;
//   oracle          the optimal finite-horizon policy of the true MDP, the
//                   ceiling no learner can pass in expectation.
//
// Deterministic given the seed. These are our own implementations.
#ifndef MANYWORLDS_CLASSIC_TABULAR_MDP_BASELINES_H_
#define MANYWORLDS_CLASSIC_TABULAR_MDP_BASELINES_H_

#include <cstdint>
#include <string>
#include <vector>

#include "manyworlds/classic/bandit_baselines.h"

namespace manyworlds::classic {

// One MDP in the env's task-state layout: rewards[s * A + a] in [0, 1],
// transitions[(s * A + a) * S + s'] with rows summing to 1.
struct TabularMdp {
  int64_t n_states = 0;
  int64_t n_actions = 0;
  std::vector<double> rewards;
  std::vector<double> transitions;
};

// The strategies' names, in the order above.
const std::vector<std::string>& TabularMdpBaselineNames();

// Runs `name` for trials_per_task trials on every MDP (all the same size).
// Throws ConfigError on an unknown name, a count < 1, MDPs of different or
// inconsistent sizes, rewards outside [0, 1] or rows that are not
// distributions.
BaselineResult RunTabularMdpBaseline(const std::string& name, const std::vector<TabularMdp>& tasks,
                                     int64_t episodes, int64_t horizon, int64_t trials_per_task,
                                     uint64_t seed);

}  // namespace manyworlds::classic

#endif  // MANYWORLDS_CLASSIC_TABULAR_MDP_BASELINES_H_
