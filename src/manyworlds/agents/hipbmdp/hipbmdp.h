// HiP-BMDP (Zhang, Sodhani, Finn, Pineau, Precup 2021, "Learning Robust State
// Abstractions for Hidden-Parameter Block MDPs"; MTRL's agent/hipbmdp.py):
// DeepMDP (agents/deepmdp) whose latent carries a learned hidden parameter
// theta per task, so that one transition and reward model covers the tasks.
//
// Each task's theta is MTRL's ThetaModel: Embedding(50) -> ReLU ->
// Linear(100) -> ReLU -> Linear(50) (here a task encoder with one hidden
// layer of 100). The actor and critics read [features, theta] with theta
// detached: theta is trained by the transition/reward and decoder losses
// and by the contrastive loss alpha (|theta - flip(theta)| - |mu(theta) -
// mu(flip(theta))|)^2 (norms over the batch, flip reversing its rows, the
// predicted next latents mu detached; MTRL's update_task_encoder), with one
// Adam step per update (lr encoder_lr). Defaults as MTRL's hipbmdp configs:
// config/agent/hipbmdp.yaml and config/agent/components/hipbmdp_multitask.yaml
// (contrastive alpha 0.01, theta 50-d, Adam 1e-3), on SAC-AE's.
//
// Differences from MTRL: MTRL's embedding table has padding_idx 0, so the
// task with index 0 keeps a zero embedding that never trains (its MT-HiPBMDP
// envs index from 1, our tasks from 0); ours trains every row. Held-out
// tasks (the trainer's meta-test, e.g. MTRL's interpolation and
// extrapolation finger sizes in configs/finger_spin_hipbmdp.yaml) are acted
// on with the mean of the trained thetas, MTRL's mean_train
// (ActorState::held_out_tasks).
#ifndef MANYWORLDS_AGENTS_HIPBMDP_HIPBMDP_H_
#define MANYWORLDS_AGENTS_HIPBMDP_HIPBMDP_H_

#include <cstdint>
#include <vector>

#include "manyworlds/agents/deepmdp/deepmdp.h"

namespace manyworlds::agents {

struct HipBmdpConfig : DeepMdpConfig {
  double contrastive_alpha = 0.01;

  HipBmdpConfig();
  template <class F>
  void VisitFields(F&& f) {
    DeepMdpConfig::VisitFields(f);
    MANYWORLDS_VISIT_FIELDS(f, contrastive_alpha);
  }
  // Throws ConfigError naming the first bad field (HiP-BMDP needs
  // architecture task_encoder with critic_trains_task_encoder false).
  void Validate() const;
};

class HipBmdpLearner : public DeepMdpLearner {
 public:
  HipBmdpLearner(const HipBmdpConfig& config, int64_t obs_dim, int64_t action_dim,
                 int64_t num_tasks, const std::vector<int64_t>& frame_shape);
};

}  // namespace manyworlds::agents

#endif  // MANYWORLDS_AGENTS_HIPBMDP_HIPBMDP_H_
