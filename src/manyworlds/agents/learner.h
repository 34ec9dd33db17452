// Learner interfaces, one per algorithm family. A learner improves an Actor
// from data; it knows no env, returns Metrics and never prints.
//   OffPolicyLearner  SAC and its multi-task variants: Update(transition batch)
//   OnPolicyLearner   PPO, TRPO (and the inner learners of MAML, RL2): Update(rollout)
// The loops that feed them live in experiments/ (one per family).
#ifndef MANYWORLDS_AGENTS_LEARNER_H_
#define MANYWORLDS_AGENTS_LEARNER_H_

#include <torch/torch.h>

#include "manyworlds/agents/actor.h"
#include "manyworlds/agents/batch.h"
#include "manyworlds/agents/metrics.h"
#include "manyworlds/rl/rollout_buffer.h"

namespace manyworlds::agents {

class Learner {
 public:
  virtual ~Learner() = default;
  // The policy as a batched actor (sampling and deterministic modes).
  virtual Actor& AsActor() = 0;
  // Full training state (networks, optimizers, generators, counters).
  virtual void Save(torch::serialize::OutputArchive& archive) const = 0;
  // Throws Error on a checkpoint of another algorithm, architecture or size.
  virtual void Load(torch::serialize::InputArchive& archive) = 0;
};

class OffPolicyLearner : public Learner {
 public:
  virtual Metrics Update(const Batch& batch) = 0;
};

class OnPolicyLearner : public Learner {
 public:
  // One iteration's optimisation on a full rollout (obs, actions, log_probs,
  // rewards and episode flags filled; values and advantages are the
  // learner's to compute).
  virtual Metrics Update(rl::RolloutBuffer& rollout) = 0;
  // Updates done so far (restored by Load).
  virtual int64_t num_updates() const = 0;
  // True for meta-learners trained on trials (RL2): an iteration's rounds
  // are one trial per env, every round of it on the same task variation,
  // and the actor is told where trials begin (ResetScope::kTrial).
  virtual bool trials() const { return false; }
  // > 0 (MAML): the loop calls Actor::Adapt after this many rounds of an
  // iteration, so the rest of the trial runs with the adapted policy.
  virtual int64_t adapt_after_rounds() const { return 0; }
  // With a support/query split of the tasks' variations: a trial's first
  // support_rounds() rounds run support variations, the rest query ones
  // (MAML: the rounds before Adapt; RL2: all but the trial's last).
  virtual int64_t support_rounds() const { return adapt_after_rounds(); }
};

}  // namespace manyworlds::agents

#endif  // MANYWORLDS_AGENTS_LEARNER_H_
