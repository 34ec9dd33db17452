#include "manyworlds/rl/rollout_buffer.h"

#include <string>

#include "manyworlds/core/error.h"
#include "manyworlds/core/memory.h"

namespace manyworlds::rl {

torch::Tensor ComputeGae(const torch::Tensor& rewards, const torch::Tensor& values,
                         const torch::Tensor& terminated, const torch::Tensor& ended,
                         const torch::Tensor& bootstrap_values, double gamma, double lambda) {
  for (const torch::Tensor* t : {&values, &terminated, &ended, &bootstrap_values}) {
    if (t->sizes() != rewards.sizes()) throw Error("ComputeGae: all inputs must be (T, N)");
  }
  if (rewards.dim() != 2 || rewards.size(0) == 0) throw Error("ComputeGae: inputs must be (T, N)");
  const int64_t steps = rewards.size(0), envs = rewards.size(1);
  const torch::Tensor r = rewards.to(torch::kFloat64).contiguous();
  const torch::Tensor v = values.to(torch::kFloat64).contiguous();
  const torch::Tensor term = terminated.to(torch::kFloat64).contiguous();
  const torch::Tensor end = ended.to(torch::kFloat64).contiguous();
  const torch::Tensor boot = bootstrap_values.to(torch::kFloat64).contiguous();
  const double* pr = r.data_ptr<double>();
  const double* pv = v.data_ptr<double>();
  const double* pt = term.data_ptr<double>();
  const double* pe = end.data_ptr<double>();
  const double* pb = boot.data_ptr<double>();
  for (int64_t n = 0; n < envs; ++n) {
    if (pe[(steps - 1) * envs + n] == 0.0) {
      throw Error("ComputeGae: the last step must end every episode (env " + std::to_string(n) +
                  " continues)");
    }
  }
  torch::Tensor adv = torch::empty({steps, envs}, torch::kFloat64);
  double* pa = adv.data_ptr<double>();
  // Backward in time; the running GAE restarts wherever an episode ended.
  for (int64_t n = 0; n < envs; ++n) {
    double running = 0.0;
    for (int64_t t = steps - 1; t >= 0; --t) {
      const int64_t i = t * envs + n;
      double next_value, carry;
      if (pe[i] != 0.0) {
        next_value = pt[i] != 0.0 ? 0.0 : pb[i];
        carry = 0.0;
      } else {
        next_value = pv[i + envs];
        carry = running;
      }
      const double delta = pr[i] + gamma * next_value - pv[i];
      running = delta + gamma * lambda * carry;
      pa[i] = running;
    }
  }
  return adv.to(torch::kFloat32);
}

RolloutBuffer::RolloutBuffer(int64_t steps, int64_t envs, int64_t obs_dim, int64_t action_dim)
    : steps_(steps), envs_(envs) {
  if (steps <= 0 || envs <= 0 || obs_dim <= 0 || action_dim <= 0) {
    throw ConfigError("RolloutBuffer: steps, envs, obs_dim and action_dim must be > 0");
  }
  // Tensors below plus the advantages and returns computed later, float32.
  const double cells = static_cast<double>(steps) * static_cast<double>(envs);
  CheckMemoryEstimate(4.0 * cells * (2.0 * obs_dim + action_dim + 10.0),
                      "a rollout of " + std::to_string(steps) + " steps x " + std::to_string(envs) +
                          " envs (obs " + std::to_string(obs_dim) + ")",
                      "the steps per iteration (agent.batch_size) or the number of envs");
  obs = torch::zeros({steps, envs, obs_dim}, torch::kFloat32);
  actions = torch::zeros({steps, envs, action_dim}, torch::kFloat32);
  log_probs = torch::zeros({steps, envs}, torch::kFloat32);
  values = torch::zeros({steps, envs}, torch::kFloat32);
  rewards = torch::zeros({steps, envs}, torch::kFloat32);
  terminated = torch::zeros({steps, envs}, torch::kFloat32);
  ended = torch::zeros({steps, envs}, torch::kFloat32);
  final_obs = torch::zeros({steps, envs, obs_dim}, torch::kFloat32);
  bootstrap_values = torch::zeros({steps, envs}, torch::kFloat32);
  episode_steps = torch::zeros({steps, envs}, torch::kFloat32);
  task_index = torch::zeros({envs}, torch::kInt64);
}

void RolloutBuffer::ComputeAdvantages(double gamma, double lambda) {
  advantages = ComputeGae(rewards, values, terminated, ended, bootstrap_values, gamma, lambda);
  returns = advantages + values;
}

torch::Tensor RolloutBuffer::DiscountedReturns(double gamma) const {
  return ComputeGae(rewards, values, terminated, ended, bootstrap_values, gamma, 1.0) + values;
}

torch::Tensor RolloutBuffer::FlatTasks() const {
  return task_index.unsqueeze(0).expand({steps_, envs_}).reshape({-1});
}

}  // namespace manyworlds::rl
