// The classical bandit strategies the RL2 paper compares with (its Table 1),
// for the same task distribution as the `bandit` env: k Bernoulli arms,
// trials of n pulls, the total reward of a trial as the score.
//
//   random    a uniformly random arm every pull;
//   greedy    the arm with the highest posterior mean under Beta(1, 1)
//             priors (ties: fewer pulls, then the lower index);
//   ucb1      each arm once, then argmax mean + sqrt(2 ln t / n_a) (Auer et
//             al. 2002; t = pulls so far);
//   thompson  Thompson sampling with Beta(1, 1) priors.
//
// Deterministic given the seed. These are our own implementations; the
// paper's numbers (random 5.0, UCB1 6.7, Thompson 5.7, Gittins 6.6 for
// n = 10, k = 5) come from its own code and tuning.
#ifndef MANYWORLDS_CLASSIC_BANDIT_BASELINES_H_
#define MANYWORLDS_CLASSIC_BANDIT_BASELINES_H_

#include <cstdint>
#include <string>
#include <vector>

namespace manyworlds::classic {

// The strategies' names, in the order above.
const std::vector<std::string>& BanditBaselineNames();

// A strategy's score over all trials of all tasks.
struct BaselineResult {
  std::string name;
  double mean_trial_return = 0.0;  // mean total reward of a trial
  double standard_error = 0.0;
};

// Runs `name` for trials_per_task trials of `pulls` pulls on every task (one
// vector of arm probabilities each, all the same size >= 2). Throws
// ConfigError on an unknown name, bad sizes or probabilities outside [0, 1].
BaselineResult RunBanditBaseline(const std::string& name,
                                       const std::vector<std::vector<double>>& tasks,
                                       int64_t pulls, int64_t trials_per_task, uint64_t seed);

}  // namespace manyworlds::classic

#endif  // MANYWORLDS_CLASSIC_BANDIT_BASELINES_H_
