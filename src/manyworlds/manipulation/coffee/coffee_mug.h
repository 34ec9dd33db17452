// coffee-push and coffee-pull (Meta-World v3, reward version "v2"): move
// the mug over the table, toward or away from the coffee machine.
//   coffee-push: mug in [(-0.1, 0.55, -0.001), (0.1, 0.65, 0.001)], goal in
//     [(-0.05, 0.7, -0.001), (0.05, 0.75, 0.001)], the machine 0.22 m
//     behind the goal.
//   coffee-pull: mug in [(-0.05, 0.7, -0.001), (0.05, 0.75, 0.001)], the
//     machine 0.22 m behind it; goal in
//     [(-0.1, 0.55, -0.001), (0.1, 0.65, 0.001)].
//   Both: mug and goal >= 0.15 m apart in xy; hand starts at (0, 0.4, 0.2),
//     bounds (-0.5, 0.4, 0.05)-(0.5, 1, 0.5); obs[4:7] is the mug's foot
//     (v3's body "obj"), obs[7:11] its (x, y, z, w) orientation; obj_init is
//     the drawn start (v3's obj_init_pos), whose height the mug leaves as it
//     settles (coffee.h).
//   reward: d = |(mug - goal) (2, 2, 1)|; in_place = tol(d, (0, 0.05),
//     margin |(mug_init - goal) (2, 2, 1)|); g = the shared caging term,
//     medium density (object radius 0.02, pads 0.05, reach 0.04, xz 0.05,
//     gripper effort 0.7); H(g, in_place), + 1 + 5 in_place with the tcp
//     within 4 cm of the foot and obs[3] > 0; 10 with d < 0.05.
//   info: success |mug - goal| <= 0.07 (unweighted); near_object |tcp - mug|
//     <= 0.03; grasp_success the pads touching the main object with
//     obs[3] > 0: v3's main object is the mug's visual mesh, which nothing
//     touches, so it is always 0, and ours (obj_geom, a visual copy of the
//     cup) is too; grasp_reward g; in_place_reward in_place; obj_to_target
//     |mug - goal|.
//   (tol: long-tail tolerance; H: Hamacher product.)
// Our mug is 4.2 cm tall where v3's is 6.6 cm, so that our gripper grasps
// it with the tcp inside those 3 and 4 cm of the foot, as v3's arm does
// (assets/coffee_mug.xml).
//   v1 (both): reward = reach + max(progress(xy distance to the goal), 0)
//     once |tcp - obj| < 0.05, max_dist = that distance at reset
//     (maxPushDist, maxPullDist); reach = -|tcp - obj| (push), and in
//     coffee-pull v3's -|(obj.x, obj.y, tcp_init.z)| (the norm of a position,
//     not a distance, so its "near" branch is never taken; kept as v3 has
//     it); info from v1's zeros: success |obj - goal| <= 0.07, near_object 1.
#ifndef MANYWORLDS_MANIPULATION_COFFEE_COFFEE_MUG_H_
#define MANYWORLDS_MANIPULATION_COFFEE_COFFEE_MUG_H_

#include <string>

#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/sawyer_task.h"

namespace manyworlds::manipulation {

class CoffeeMugTask : public SawyerTask {
 protected:
  // machine_at_goal: the machine stands behind the goal (push), else behind
  // the mug's start (pull).
  CoffeeMugTask(SawyerTaskConfig config, bool machine_at_goal, SawyerOptions options);
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
  RewardTerms ComputeRewardV1(const SawyerState& state,
                              std::span<const float> action) const override;
  void InitTaskState(SawyerState& state) const override;
  void PlaceObjects(mjModel* m, mjData* d) override;
  // The ranges: the mug goes between the front of the machine and a spot
  // away from it, toward the machine when machine_at_goal.
  static SawyerTaskConfig Config(std::string id, std::string description, std::string xml_file,
                                 bool machine_at_goal);

 private:
  bool machine_at_goal_;
  int machine_ = -1;  // body
  int mug_qpos_ = -1, mug_dof_ = -1;
};

class CoffeePush : public CoffeeMugTask {
 public:
  explicit CoffeePush(SawyerOptions options = {});
  static SawyerTaskConfig Config();
};

class CoffeePull : public CoffeeMugTask {
 public:
  explicit CoffeePull(SawyerOptions options = {});
  static SawyerTaskConfig Config();
};

// Grasps the cup from above, the tcp 2 cm above its foot (the palm clear of
// its rim; coming down 1 cm in front of its middle, so that the palm stays
// clear of the spout), and carries it, 2 cm up, to the goal.
class CoffeeMugScriptedPolicy : public Policy {
 public:
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;
};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_COFFEE_COFFEE_MUG_H_
