// The batched policy interface every algorithm exposes to collection,
// evaluation and `rollout --policy checkpoint:RUN_DIR`.
//
// An Actor maps a batch of env observations (N, obs_dim) and task indices
// (N) to actions (N, action_dim). Stateful actors (RL2's recurrent hidden
// state, PEARL's latent and context, MAML's adapted parameters) keep their
// per-env state in an ActorState that the caller owns and passes back on
// every call, and are told where episodes, trials and tasks begin again.
//
// Action convention: Box actions are in the policy's own units; the caller
// clips them to [-1, 1] and scales them to the env's bounds. Discrete
// actions are indices held as floats (one column).
#ifndef MANYWORLDS_AGENTS_ACTOR_H_
#define MANYWORLDS_AGENTS_ACTOR_H_

#include <cstdint>

#include <torch/torch.h>

namespace manyworlds::agents {

enum class ActMode {
  kSample,         // exploration: draw from the policy
  kDeterministic,  // evaluation: the mean (Gaussian) or the most likely action
};

// Which boundary Reset marks for the envs in its mask.
enum class ResetScope { kEpisode, kTrial, kTask };

// Per-env state of a stateful actor; feed-forward actors leave it empty.
struct ActorState {
  torch::Tensor hidden;  // recurrent state (layers, N, H)
  torch::Tensor latent;  // a task latent per env (N, Z)
};

struct ActOutput {
  torch::Tensor action;    // (N, action_dim)
  torch::Tensor log_prob;  // (N) log-probability of action, when the policy has one
  // (N, Z) the latent the actions were conditioned on (TE-PPO), else undefined;
  // on-policy loops store it with the rollout.
  torch::Tensor latent;
};

class Actor {
 public:
  virtual ~Actor() = default;
  virtual ActorState Initial(int64_t /*num_envs*/) { return {}; }
  // Runs in inference mode; the outputs are inference tensors (copy them out).
  virtual ActOutput Act(const torch::Tensor& obs, const torch::Tensor& task_index,
                        ActorState& state, ActMode mode) = 0;
  // envs: (N) bool, true where the boundary applies.
  virtual void Reset(const torch::Tensor& /*envs*/, ResetScope /*scope*/, ActorState& /*state*/) {}
};

}  // namespace manyworlds::agents

#endif  // MANYWORLDS_AGENTS_ACTOR_H_
