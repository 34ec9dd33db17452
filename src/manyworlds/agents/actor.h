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

#include <torch/torch.h>

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace manyworlds::agents {

enum class ActMode {
  kSample,         // exploration: draw from the policy
  kDeterministic,  // evaluation: the mean (Gaussian) or the most likely action
};

// Which boundary Reset marks for the envs in its mask.
enum class ResetScope { kEpisode, kTrial, kTask };

// Per-env state of a stateful actor, as named entries each actor chooses for
// itself (RL2: "hidden", "context"; TE-PPO: "latent"; PEARL: "latent",
// "context", "history"; MAML: "history", "adapted"), so that a new algorithm
// adds names, not fields; feed-forward actors leave it empty. Every tensor
// has the env first (N, ...).
struct ActorState {
  // What a step may change per env; a protocol that holds some envs still
  // (the meta-test's waiting envs) keeps these rows as they were.
  std::map<std::string, torch::Tensor> tensors;
  // Per-step records and per-parameter stacks (MAML's adapted parameters,
  // one tensor per parameter); rows a waiting env must not count are marked
  // by StepOutcome::valid instead.
  std::map<std::string, std::vector<torch::Tensor>> lists;
  // When set, sampling draws from this generator instead of the learner's:
  // an evaluation protocol seeds its own, so its sampled episodes depend only
  // on its seed and never move the training's random stream.
  std::optional<at::Generator> generator;
  // True in the training loop's state: the learner's next Update learns from
  // the episodes acted here, so an actor may keep what it computed for them
  // (MAML keeps its differentiable inner step from Adapt for the update).
  bool learning = false;
  // True in a meta-test on held-out tasks: task_index numbers the held-out
  // tasks, not training ones, so an actor conditioned on learned per-task
  // encodings uses what it learned across tasks instead (SAC's task_encoder,
  // HiP-BMDP: the mean of the trained encodings, MTRL's mean_train).
  bool held_out_tasks = false;
};

// The generator an actor samples from for this state.
inline at::Generator& SamplingGenerator(ActorState& state, at::Generator& own) {
  return state.generator ? *state.generator : own;
}

// What the envs did with the actions of the last Act, for actors that build
// their context from it (WantsOutcomes): RL2's previous action, reward and
// episode flag; MAML's and PEARL's transitions. The tensors may view the
// caller's buffers and are valid only during Observe: copy what you keep.
struct StepOutcome {
  torch::Tensor action;  // (N, action_dim) as Act returned them
  torch::Tensor reward;  // (N) float
  torch::Tensor ended;   // (N) float 0/1: the episode ended (terminated or truncated)
  torch::Tensor obs;     // (N, obs_dim) the observations the actions were taken in
  // (N) float 0/1: 0 where the row does not count (an env waiting for the
  // others in a meta-test phase); undefined = every row counts.
  torch::Tensor valid;
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
  // True if the caller must pass every step's outcome to Observe.
  virtual bool WantsOutcomes() const { return false; }
  virtual void Observe(const StepOutcome& /*outcome*/, ActorState& /*state*/) {}
  // The end of the exploration phase of a meta-test for the envs in the mask:
  // the actor adapts to what it observed (MAML: inner gradient steps; PEARL:
  // the posterior over its latent). RL2's adaptation is its hidden state, so
  // it does nothing here.
  virtual void Adapt(const torch::Tensor& /*envs*/, ActorState& /*state*/) {}
  // True for actors whose Box actions are already in the env's units (an
  // env's own scripted or random policy): the caller passes them on as they
  // are instead of clipping and scaling them.
  virtual bool ActsInEnvUnits() const { return false; }
};

// Stops the rows of envs in `mask` (N, bool) counting in a recorded
// history: every step (N, d) holds its rows' validity weight in its last
// column, which becomes 0 for those rows (each step is replaced by a copy,
// never written into in place).
inline void ForgetHistoryRows(std::vector<torch::Tensor>& history, const torch::Tensor& mask) {
  const torch::Tensor keep = mask.logical_not().to(torch::kFloat32);
  for (torch::Tensor& row : history) {
    row = row.clone();
    row.select(1, row.size(1) - 1).mul_(keep);
  }
}

// Starts `state` over with actor.Initial(num_envs), keeping the generator a
// protocol gave it, unless its tensor `key` holds num_envs rows. Returns true
// if it started over.
inline bool RestartUnlessSized(Actor& actor, ActorState& state, const std::string& key,
                               int64_t num_envs) {
  const torch::Tensor& t = state.tensors[key];
  if (t.defined() && t.size(0) == num_envs) return false;
  std::optional<at::Generator> own = state.generator;
  const bool learning = state.learning;
  const bool held_out = state.held_out_tasks;
  state = actor.Initial(num_envs);
  state.generator = own;
  state.learning = learning;
  state.held_out_tasks = held_out;
  return true;
}

}  // namespace manyworlds::agents

#endif  // MANYWORLDS_AGENTS_ACTOR_H_
