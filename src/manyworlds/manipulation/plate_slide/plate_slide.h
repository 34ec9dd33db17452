// The plate-slide family (Meta-World v3's plate-slide, plate-slide-side,
// plate-slide-back, plate-slide-back-side): a 10 x 10 cm plate on two
// slide joints from its channel at (0, 0.6) (x in [-0.4, 0.3], y in
// [-0.05, 0.3]: the travel v3's soft limits allow) pushed into, or pulled
// out of, a frame with low rails.
//   plate-slide: starts at (0, 0.6); goal (the frame) in (-0.1, 0.85)-
//     (0.1, 0.9), z 0; reward 8 H(g, in_place), 10 within 0.05, where
//     g = tol(|tcp - plate|, (0, 0.05), margin |tcp_init - obj_init|) and
//     in_place = tol(|plate - goal|, (0, 0.05), margin |obj_init - goal|).
//   plate-slide-side: starts at (0, 0.6); goal in (-0.3, 0.54)-(-0.25, 0.66),
//     z 0; the frame fixed at (-0.3, 0.6), open toward +x.
//   plate-slide-back: starts at (0, 0.75) in the frame at (0, 0.85)
//     (obj_init (0, 0.85, 0), as v3); goal in (-0.1, 0.6)-(0.1, 0.6), z 0.015.
//   plate-slide-back-side: starts at (-0.15, 0.6) in the frame at
//     (-0.25, 0.6) (obj_init (-0.25, 0.6, 0)); goal in (-0.05, 0.6)-
//     (0.15, 0.6), z 0.015.
//   The three others: margins less 0.05; reward 1.5 g, or 2 + 7 in_place
//     with the tcp at most 3 cm high and within 7 cm of the plate; 10
//     within 0.05.
//   info (all): success |plate - goal| <= 0.07; near_object tcp within
//     0.03; grasp_success 0; grasp_reward g.
//   v1 (all four): reward = -|tcp - obj| + max(progress(xy distance to the
//     goal), 0) within 5 cm, max_dist = that distance at reset (maxDist);
//     info from v1's zeros: success <= 0.07, near_object 1.
#ifndef MANYWORLDS_MANIPULATION_PLATE_SLIDE_PLATE_SLIDE_H_
#define MANYWORLDS_MANIPULATION_PLATE_SLIDE_PLATE_SLIDE_H_

#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/sawyer_task.h"

namespace manyworlds::manipulation {

// What distinguishes the four tasks.
struct PlateSlideVariant {
  Vec3 plate_start{};        // the plate's start, from the slide joints' zero
  bool frame_at_goal = false;  // plate-slide: the frame is the goal
  Vec3 frame{};              // otherwise the frame's fixed position
  bool low_push_reward = false;  // the 1.5 g / 2 + 7 in_place reward
};

class PlateSlideTask : public SawyerTask {
 protected:
  PlateSlideTask(SawyerTaskConfig config, PlateSlideVariant variant, SawyerOptions options);
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
  RewardTerms ComputeRewardV1(const SawyerState& state,
                              std::span<const float> action) const override;
  void InitTaskState(SawyerState& state) const override;
  void PlaceObjects(mjModel* m, mjData* d) override;

 private:
  PlateSlideVariant variant_;
  int frame_ = -1;                  // body
  int plate_x_ = -1, plate_y_ = -1;  // qpos addresses
};

class PlateSlide : public PlateSlideTask {
 public:
  explicit PlateSlide(SawyerOptions options = {});
  static SawyerTaskConfig Config();
};

class PlateSlideSide : public PlateSlideTask {
 public:
  explicit PlateSlideSide(SawyerOptions options = {});
  static SawyerTaskConfig Config();
};

class PlateSlideBack : public PlateSlideTask {
 public:
  explicit PlateSlideBack(SawyerOptions options = {});
  static SawyerTaskConfig Config();
};

class PlateSlideBackSide : public PlateSlideTask {
 public:
  explicit PlateSlideBackSide(SawyerOptions options = {});
  static SawyerTaskConfig Config();
};

// Fingers closed into a paddle: down behind the plate (on the side away
// from the goal), then push it to the goal.
class PlateSlideScriptedPolicy : public Policy {
 public:
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;
};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_PLATE_SLIDE_PLATE_SLIDE_H_
