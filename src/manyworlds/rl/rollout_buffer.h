// On-policy rollout storage: T steps of N envs, with GAE.
//
//   RolloutBuffer buffer(T, N, obs_dim, action_dim);
//   for t: buffer.Store(t, obs, action, log_prob, value, reward, terminated,
//                       ended, bootstrap_value, episode_step);
//   buffer.ComputeAdvantages(gamma, lambda);   // fills advantages, returns
//
// The collector fills obs, actions, log_probs, rewards, terminated, ended,
// final_obs, episode_steps and task_index; the learner fills values and
// bootstrap_values (from its value function or baseline) before GAE.
//
// Episode boundaries follow Gymnasium exactly: where an episode `ended` at
// step t, GAE does not carry over to t + 1; if it ended because the MDP
// `terminated`, the next value is 0, otherwise (a time-limit truncation, or
// the collector cutting the episode at the end of a round) the next value is
// `bootstrap_value`, the value of the episode's final observation. The last
// step of a buffer must end every episode (the collector cuts them), so the
// buffer never needs a value past its end.
#ifndef MANYWORLDS_RL_ROLLOUT_BUFFER_H_
#define MANYWORLDS_RL_ROLLOUT_BUFFER_H_

#include <cstdint>

#include <torch/torch.h>

namespace manyworlds::rl {

// Generalised advantage estimation over (T, N) float tensors (ended and
// terminated as 0/1 floats). Returns the advantages (T, N); the lambda-
// returns are advantages + values. Throws Error on shape mismatches or if
// the last row does not end every episode.
torch::Tensor ComputeGae(const torch::Tensor& rewards, const torch::Tensor& values,
                         const torch::Tensor& terminated, const torch::Tensor& ended,
                         const torch::Tensor& bootstrap_values, double gamma, double lambda);

class RolloutBuffer {
 public:
  // Throws ConfigError on non-positive sizes.
  RolloutBuffer(int64_t steps, int64_t envs, int64_t obs_dim, int64_t action_dim);

  int64_t steps() const { return steps_; }
  int64_t envs() const { return envs_; }
  int64_t size() const { return steps_ * envs_; }

  // (T, N, ...) storage, written by the collector.
  torch::Tensor obs;              // (T, N, obs_dim)
  torch::Tensor actions;          // (T, N, action_dim) as sampled (unclipped)
  torch::Tensor log_probs;        // (T, N)
  torch::Tensor values;           // (T, N) V(obs) (or a baseline's prediction)
  torch::Tensor rewards;          // (T, N)
  torch::Tensor terminated;       // (T, N) 0/1
  torch::Tensor ended;            // (T, N) 0/1: terminated, truncated or cut
  torch::Tensor final_obs;        // (T, N, obs_dim) last observation where ended, else 0
  torch::Tensor bootstrap_values; // (T, N) V(final obs) where ended and not terminated
  torch::Tensor episode_steps;    // (T, N) steps into the episode before this one
  torch::Tensor task_index;       // (N) int64
  // (T, N, Z) the actor's latent at each step, for latent-conditioned
  // policies (TE-PPO); undefined otherwise (the loop allocates it).
  torch::Tensor latents;
  // Filled by ComputeAdvantages.
  torch::Tensor advantages;       // (T, N)
  torch::Tensor returns;          // (T, N) advantages + values

  void ComputeAdvantages(double gamma, double lambda);
  // Discounted Monte-Carlo returns (GAE with lambda = 1), bootstrapped at
  // truncations: what the linear feature baseline is fitted to.
  torch::Tensor DiscountedReturns(double gamma) const;

  // Flat (T * N) views, row r = t * N + n.
  torch::Tensor FlatObs() const { return obs.reshape({size(), -1}); }
  torch::Tensor FlatActions() const { return actions.reshape({size(), -1}); }
  torch::Tensor FlatTasks() const;

 private:
  int64_t steps_, envs_;
};

}  // namespace manyworlds::rl

#endif  // MANYWORLDS_RL_ROLLOUT_BUFFER_H_
