#include "manyworlds/classic/bandit_baselines.h"

#include <algorithm>
#include <cmath>
#include <functional>

#include "manyworlds/core/error.h"
#include "manyworlds/core/rng.h"

namespace manyworlds::classic {
namespace {

struct ArmStats {
  std::vector<int64_t> pulls, wins;
};

// A strategy picks an arm from the statistics so far (t = pulls so far).
using Strategy = std::function<size_t(const ArmStats&, int64_t t, Rng&)>;

// Beta(a, b) for integers a, b >= 1: the a-th smallest of a + b - 1 uniforms.
double BetaInt(int64_t a, int64_t b, Rng& rng) {
  std::vector<double> u(static_cast<size_t>(a + b - 1));
  for (double& x : u) x = rng.Uniform();
  std::nth_element(u.begin(), u.begin() + (a - 1), u.end());
  return u[static_cast<size_t>(a - 1)];
}

size_t ArgMax(size_t k, const std::function<double(size_t)>& score) {
  size_t best = 0;
  for (size_t a = 1; a < k; ++a) {
    if (score(a) > score(best)) best = a;
  }
  return best;
}

Strategy Find(const std::string& name) {
  if (name == "random") {
    return [](const ArmStats& s, int64_t, Rng& rng) {
      return static_cast<size_t>(rng.UniformInt(s.pulls.size()));
    };
  }
  if (name == "greedy") {
    return [](const ArmStats& s, int64_t, Rng&) {
      // posterior mean, then fewer pulls (a small bonus below any mean gap)
      return ArgMax(s.pulls.size(), [&](size_t a) {
        return (s.wins[a] + 1.0) / (s.pulls[a] + 2.0) - 1e-9 * static_cast<double>(s.pulls[a]);
      });
    };
  }
  if (name == "ucb1") {
    return [](const ArmStats& s, int64_t t, Rng&) {
      for (size_t a = 0; a < s.pulls.size(); ++a) {
        if (s.pulls[a] == 0) return a;
      }
      return ArgMax(s.pulls.size(), [&](size_t a) {
        const double n = static_cast<double>(s.pulls[a]);
        return s.wins[a] / n + std::sqrt(2.0 * std::log(static_cast<double>(t)) / n);
      });
    };
  }
  if (name == "thompson") {
    return [](const ArmStats& s, int64_t, Rng& rng) {
      std::vector<double> draw(s.pulls.size());
      for (size_t a = 0; a < draw.size(); ++a) {
        draw[a] = BetaInt(s.wins[a] + 1, s.pulls[a] - s.wins[a] + 1, rng);
      }
      return ArgMax(draw.size(), [&](size_t a) { return draw[a]; });
    };
  }
  std::string allowed;
  for (const std::string& n : BanditBaselineNames()) allowed += (allowed.empty() ? "" : ", ") + n;
  throw ConfigError("bandit baseline: unknown strategy '" + name + "'; allowed: " + allowed);
}

}  // namespace

const std::vector<std::string>& BanditBaselineNames() {
  static const std::vector<std::string> names = {"random", "greedy", "ucb1", "thompson"};
  return names;
}

BaselineResult RunBanditBaseline(const std::string& name,
                                       const std::vector<std::vector<double>>& tasks,
                                       int64_t pulls, int64_t trials_per_task, uint64_t seed) {
  const Strategy strategy = Find(name);
  if (tasks.empty() || pulls < 1 || trials_per_task < 1) {
    throw ConfigError("bandit baseline: need >= 1 task, pull and trial");
  }
  const size_t k = tasks.front().size();
  for (const auto& probs : tasks) {
    if (probs.size() != k || k < 2) {
      throw ConfigError("bandit baseline: every task needs the same number (>= 2) of arms");
    }
    for (double p : probs) {
      if (!(p >= 0.0 && p <= 1.0)) {
        throw ConfigError("bandit baseline: arm probabilities must be in [0, 1]");
      }
    }
  }
  Rng rng(seed);
  double sum = 0.0, sum_sq = 0.0;
  int64_t count = 0;
  for (const auto& probs : tasks) {
    for (int64_t trial = 0; trial < trials_per_task; ++trial) {
      ArmStats s{std::vector<int64_t>(k, 0), std::vector<int64_t>(k, 0)};
      double total = 0.0;
      for (int64_t t = 0; t < pulls; ++t) {
        const size_t a = strategy(s, t, rng);
        const bool win = rng.Bernoulli(probs[a]);
        ++s.pulls[a];
        s.wins[a] += win ? 1 : 0;
        total += win ? 1.0 : 0.0;
      }
      sum += total;
      sum_sq += total * total;
      ++count;
    }
  }
  BaselineResult result;
  result.name = name;
  result.mean_trial_return = sum / count;
  const double var = std::max(0.0, sum_sq / count - result.mean_trial_return * result.mean_trial_return);
  result.standard_error = std::sqrt(var / count);
  return result;
}

}  // namespace manyworlds::classic
