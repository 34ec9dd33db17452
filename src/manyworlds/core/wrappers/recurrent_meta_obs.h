// RecurrentMetaObservation: the observation of recurrent meta-RL policies,
// as Meta-World v3's RNNBasedMetaRLWrapper builds it: the env observation,
// then the action just taken (Box: as the env received it; Discrete: one-hot
// of the index), the reward times reward_scale (v3: 1/10) and the episode-end
// flag (terminated or truncated); zeros for the three after Reset.
//
// manyworlds' own RL2 builds this input inside the actor and keeps it across
// the episodes of a trial (agents/rl2/rl2.h); this wrapper is for other
// learners (e.g. a recurrent PPO in Python) on any env with a Box
// observation.
#ifndef MANYWORLDS_CORE_WRAPPERS_RECURRENT_META_OBS_H_
#define MANYWORLDS_CORE_WRAPPERS_RECURRENT_META_OBS_H_

#include <cstdint>
#include <memory>

#include "manyworlds/core/wrapper.h"

namespace manyworlds {

class RecurrentMetaObservation : public Wrapper {
 public:
  // Throws ConfigError for a non-Box observation or a non-finite scale.
  RecurrentMetaObservation(std::unique_ptr<Env> inner, double reward_scale = 0.1);

 protected:
  void DoReset(const ObsView& out) override;
  void DoStep(std::span<const float> action, const StepView& out) override;

 private:
  int64_t inner_obs_size_ = 0;
  int64_t action_size_ = 0;   // appended action values (Discrete: n)
  int64_t num_actions_ = 0;   // > 0 for Discrete
  float reward_scale_ = 0.1f;
};

}  // namespace manyworlds

#endif  // MANYWORLDS_CORE_WRAPPERS_RECURRENT_META_OBS_H_
