#include "manyworlds/classic/tabular_mdp_baselines.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <memory>

#include "manyworlds/core/error.h"
#include "manyworlds/core/rng.h"

namespace manyworlds::classic {
namespace {

constexpr double kEpsilon = 0.1;
constexpr double kRowSumTolerance = 1e-6;

// What a learner has seen of one MDP within a trial.
struct Counts {
  int64_t S, A;
  std::vector<int64_t> visits, wins;  // per (s, a)
  std::vector<int64_t> next;          // per (s, a, s')

  Counts(int64_t s, int64_t a) : S(s), A(a), visits(s * a, 0), wins(s * a, 0), next(s * a * s, 0) {}

  // The posterior mean MDP: Beta(1, 1) rewards, Dirichlet(1) transitions.
  TabularMdp Mean() const {
    TabularMdp m{S, A, std::vector<double>(S * A), std::vector<double>(S * A * S)};
    for (int64_t sa = 0; sa < S * A; ++sa) {
      m.rewards[sa] = (wins[sa] + 1.0) / (visits[sa] + 2.0);
      for (int64_t k = 0; k < S; ++k) {
        m.transitions[sa * S + k] =
            (next[sa * S + k] + 1.0) / (visits[sa] + static_cast<double>(S));
      }
    }
    return m;
  }

  // One MDP drawn from the posterior. Every shape parameter is a positive
  // integer, so Gamma(k) is a sum of k standard exponentials.
  TabularMdp Sample(Rng& rng) const {
    TabularMdp m{S, A, std::vector<double>(S * A), std::vector<double>(S * A * S)};
    for (int64_t sa = 0; sa < S * A; ++sa) {
      const double g_win = Gamma(wins[sa] + 1, rng);
      const double g_loss = Gamma(visits[sa] - wins[sa] + 1, rng);
      m.rewards[sa] = g_win / (g_win + g_loss);
      double total = 0.0;
      for (int64_t k = 0; k < S; ++k)
        total += m.transitions[sa * S + k] = Gamma(next[sa * S + k] + 1, rng);
      for (int64_t k = 0; k < S; ++k) m.transitions[sa * S + k] /= total;
    }
    return m;
  }

  static double Gamma(int64_t shape, Rng& rng) {
    double sum = 0.0;
    for (int64_t i = 0; i < shape; ++i) sum -= std::log1p(-rng.Uniform());
    return sum;
  }
};

// Q[t][s][a] of the optimal policy with `steps` steps to go (t = 0 is the
// first of them), by backward induction.
std::vector<double> PlanQ(const TabularMdp& m, int64_t steps) {
  const int64_t S = m.n_states, A = m.n_actions;
  std::vector<double> q(steps * S * A, 0.0);
  std::vector<double> v_next(S, 0.0), v(S, 0.0);
  for (int64_t t = steps - 1; t >= 0; --t) {
    for (int64_t s = 0; s < S; ++s) {
      double best = -1.0;
      for (int64_t a = 0; a < A; ++a) {
        const int64_t sa = s * A + a;
        double value = m.rewards[sa];
        for (int64_t k = 0; k < S; ++k) value += m.transitions[sa * S + k] * v_next[k];
        q[(t * S + s) * A + a] = value;
        best = std::max(best, value);
      }
      v[s] = best;
    }
    std::swap(v, v_next);
  }
  return q;
}

// The best action in row q[0..A), ties to fewer visits, then the lower index.
int64_t Best(const double* q, const int64_t* visits, int64_t A) {
  int64_t best = 0;
  for (int64_t a = 1; a < A; ++a) {
    if (q[a] > q[best] + 1e-12 || (std::abs(q[a] - q[best]) <= 1e-12 && visits[a] < visits[best])) {
      best = a;
    }
  }
  return best;
}

// A strategy chooses the action at step t of an episode in state s. It may
// keep a plan between calls (cleared at each episode start by t == 0).
class Strategy {
 public:
  virtual ~Strategy() = default;
  virtual int64_t Act(const TabularMdp& truth, const Counts& counts, int64_t s, int64_t t,
                      int64_t horizon, Rng& rng) = 0;
};

class RandomStrategy : public Strategy {
 public:
  int64_t Act(const TabularMdp& truth, const Counts&, int64_t, int64_t, int64_t,
              Rng& rng) override {
    return static_cast<int64_t>(rng.UniformInt(static_cast<uint64_t>(truth.n_actions)));
  }
};

class GreedyStrategy : public Strategy {
 public:
  explicit GreedyStrategy(double epsilon) : epsilon_(epsilon) {}
  int64_t Act(const TabularMdp& truth, const Counts& c, int64_t s, int64_t t, int64_t horizon,
              Rng& rng) override {
    if (epsilon_ > 0.0 && rng.Uniform() < epsilon_) {
      return static_cast<int64_t>(rng.UniformInt(static_cast<uint64_t>(truth.n_actions)));
    }
    const std::vector<double> q = PlanQ(c.Mean(), horizon - t);
    return Best(q.data() + s * c.A, c.visits.data() + s * c.A, c.A);
  }

 private:
  double epsilon_;
};

class PosteriorSamplingStrategy : public Strategy {
 public:
  int64_t Act(const TabularMdp&, const Counts& c, int64_t s, int64_t t, int64_t horizon,
              Rng& rng) override {
    if (t == 0) plan_ = PlanQ(c.Sample(rng), horizon);
    return Best(plan_.data() + (t * c.S + s) * c.A, c.visits.data() + s * c.A, c.A);
  }

 private:
  std::vector<double> plan_;
};

class OracleStrategy : public Strategy {
 public:
  int64_t Act(const TabularMdp& truth, const Counts& c, int64_t s, int64_t t, int64_t horizon,
              Rng&) override {
    // one strategy per MDP (RunTabularMdpBaseline): plan once, for all its trials
    if (plan_.empty()) plan_ = PlanQ(truth, horizon);
    return Best(plan_.data() + (t * c.S + s) * c.A, c.visits.data() + s * c.A, c.A);
  }

 private:
  std::vector<double> plan_;
};

const std::map<std::string, std::function<std::unique_ptr<Strategy>()>>& Registry() {
  static const std::map<std::string, std::function<std::unique_ptr<Strategy>()>> registry = {
      {"random", [] { return std::make_unique<RandomStrategy>(); }},
      {"greedy", [] { return std::make_unique<GreedyStrategy>(0.0); }},
      {"epsilon-greedy", [] { return std::make_unique<GreedyStrategy>(kEpsilon); }},
      {"psrl", [] { return std::make_unique<PosteriorSamplingStrategy>(); }},
      {"oracle", [] { return std::make_unique<OracleStrategy>(); }},
  };
  return registry;
}

void CheckTasks(const std::vector<TabularMdp>& tasks) {
  if (tasks.empty()) throw ConfigError("tabular-mdp baseline: need at least one MDP");
  const int64_t S = tasks.front().n_states, A = tasks.front().n_actions;
  if (S < 1 || A < 1) throw ConfigError("tabular-mdp baseline: need >= 1 state and action");
  for (const TabularMdp& m : tasks) {
    if (m.n_states != S || m.n_actions != A || static_cast<int64_t>(m.rewards.size()) != S * A ||
        static_cast<int64_t>(m.transitions.size()) != S * A * S) {
      throw ConfigError("tabular-mdp baseline: every MDP needs the same sizes, with " +
                        std::to_string(S * A) + " rewards and " + std::to_string(S * A * S) +
                        " transition probabilities");
    }
    for (double r : m.rewards) {
      if (!(r >= 0.0 && r <= 1.0))
        throw ConfigError("tabular-mdp baseline: rewards must be in [0, 1]");
    }
    for (int64_t sa = 0; sa < S * A; ++sa) {
      double total = 0.0;
      for (int64_t k = 0; k < S; ++k) {
        const double p = m.transitions[sa * S + k];
        if (!(p >= 0.0 && p <= 1.0)) {
          throw ConfigError("tabular-mdp baseline: transition probabilities must be in [0, 1]");
        }
        total += p;
      }
      if (std::abs(total - 1.0) > kRowSumTolerance) {
        throw ConfigError("tabular-mdp baseline: every transition row must sum to 1");
      }
    }
  }
}

}  // namespace

const std::vector<std::string>& TabularMdpBaselineNames() {
  static const std::vector<std::string> names = {"random", "greedy", "epsilon-greedy", "psrl",
                                                 "oracle"};
  return names;
}

BaselineResult RunTabularMdpBaseline(const std::string& name, const std::vector<TabularMdp>& tasks,
                                     int64_t episodes, int64_t horizon, int64_t trials_per_task,
                                     uint64_t seed) {
  const auto found = Registry().find(name);
  if (found == Registry().end()) {
    std::string allowed;
    for (const std::string& n : TabularMdpBaselineNames())
      allowed += (allowed.empty() ? "" : ", ") + n;
    throw ConfigError("tabular-mdp baseline: unknown strategy '" + name + "'; allowed: " + allowed);
  }
  if (episodes < 1 || horizon < 1 || trials_per_task < 1) {
    throw ConfigError("tabular-mdp baseline: episodes, horizon and trials must each be >= 1");
  }
  CheckTasks(tasks);
  Rng rng(seed);
  double sum = 0.0, sum_sq = 0.0;
  int64_t count = 0;
  for (const TabularMdp& mdp : tasks) {
    const std::unique_ptr<Strategy> strategy = found->second();
    for (int64_t trial = 0; trial < trials_per_task; ++trial) {
      Counts counts(mdp.n_states, mdp.n_actions);
      double total = 0.0;
      for (int64_t episode = 0; episode < episodes; ++episode) {
        int64_t s = 0;
        for (int64_t t = 0; t < horizon; ++t) {
          const int64_t a = strategy->Act(mdp, counts, s, t, horizon, rng);
          const int64_t sa = s * mdp.n_actions + a;
          const bool win = rng.Bernoulli(mdp.rewards[sa]);
          // the next state by inverse CDF, as the env draws it
          double u = rng.Uniform();
          int64_t next = mdp.n_states - 1;
          for (int64_t k = 0; k < mdp.n_states; ++k) {
            u -= mdp.transitions[sa * mdp.n_states + k];
            if (u < 0.0) {
              next = k;
              break;
            }
          }
          ++counts.visits[sa];
          counts.wins[sa] += win ? 1 : 0;
          ++counts.next[sa * mdp.n_states + next];
          total += win ? 1.0 : 0.0;
          s = next;
        }
      }
      sum += total;
      sum_sq += total * total;
      ++count;
    }
  }
  BaselineResult result;
  result.name = name;
  result.mean_trial_return = sum / static_cast<double>(count);
  const double var = std::max(0.0, sum_sq / static_cast<double>(count) -
                                       result.mean_trial_return * result.mean_trial_return);
  result.standard_error = std::sqrt(var / static_cast<double>(count));
  return result;
}

}  // namespace manyworlds::classic
