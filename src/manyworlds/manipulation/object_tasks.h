// Pieces shared by the free-object tasks (push, pick-place, sweep, peg,
// hole, basketball, shelf-place, soccer, ...): one loose object the gripper
// moves, often next to a static fixture (box, hoop, shelf, net) that is
// moved to the variation's goal at reset.
#ifndef MANYWORLDS_MANIPULATION_OBJECT_TASKS_H_
#define MANYWORLDS_MANIPULATION_OBJECT_TASKS_H_

#include <mujoco/mujoco.h>

#include <optional>

#include "manyworlds/manipulation/reward_utils.h"
#include "manyworlds/manipulation/sawyer_task.h"

namespace manyworlds::manipulation {

// Gripper caging of the point `obj` (usually state.obj), from the pads, tcp
// and initial positions in `state`.
double CageObject(const SawyerState& state, const Vec3& obj, double gripper_action,
                  const CagingParams& params);

// Pieces of Meta-World v3's task-local caging terms (pick-place, sweep,
// sweep-into have their own, unlike the shared GripperCagingReward):
// PadCagingY: Hamacher product over both pads of the long-tail tolerance of
// the pad's signed y offset from the object (left pad - obj, obj - right
// pad) within (low, high), each with margin | |obj_y - pad_y| - 0.05 |.
// (v3 takes that margin from the pads "at reset", which it stores as views
// of the live positions: the current pads. We compute what v3 computes.)
double PadCagingY(const SawyerState& state, double low, double high);
// TcpCagingXz: long-tail tolerance of the tcp-object distance in xz within
// (0, radius), margin = the reset tcp-object xz distance - radius.
double TcpCagingXz(const SawyerState& state, double radius);
// sweep and sweep-into: caging = H(PadCagingY(r, 0.05), TcpCagingXz(xz));
// gripping = PadCagingY(r, r + band) once caging > 0.95 (no gripper-action
// term); result (caging + gripping) / 2.
double SweepCaging(const SawyerState& state, double obj_radius, double band, double xz_radius);

// The Meta-World "carrying" test: tcp within `tcp_radius` of the object, the
// gripper not shut (opening > 0) and the object `lift` above its start.
bool HeldAndLifted(const SawyerState& state, double tcp_radius, double lift);

// The gripper is not shut and the object is 3 cm above its start (info
// grasp_success of basketball and the handle pulls).
bool OpenAndLifted(const SawyerState& state);

// info grasp_success: a pad touches the object, the gripper is not shut and
// the object is 2 cm above its start.
double GraspSuccess(const SawyerState& state);

// |diag(weights) (a - b)|: weighting an axis makes it count more.
double WeightedDistance(const Vec3& a, const Vec3& b, const Vec3& weights);

// v3's reach for pushing a lever or lock up from below: the hand's
// "shoulder", 5.5 cm behind and 7 cm above the hand, to the object point,
// weighted by `scale` (distance); ready = its long-tail tolerance within
// 2 cm, margin the same distance at reset, from the tcp's start to
// `obj_at_reset`.
struct ShoulderReach {
  double distance = 0;
  double ready = 0;
};
ShoulderReach ReachWithShoulder(const SawyerState& state, const Vec3& obj_at_reset,
                                const Vec3& scale);

// Meta-World v3's funnel-shaped floor around a point (pick-out-of-hole,
// bin-picking, box-close): the height the hand should keep at horizontal
// distance `radius` from it, 0 within `threshold`, else
// scale * ln(radius - threshold) + height.
double FunnelFloor(double radius, double threshold, double scale, double height);
// 1 when `z` is at or above `floor`, else the long-tail tolerance of
// floor - z within (0, 0.01) with `margin`.
double AboveFloor(double z, double floor, double margin);

Vec3 SitePosition(const mjData* d, int site);

// Moves a static (jointless, world-child) body so its frame is at `pos`.
// Every env owns its model, so this changes only this env's scene.
void PlaceFixture(mjModel* m, int body, const Vec3& pos);

// The object's progress toward the goal most free-object rewards read: the
// long-tail tolerance of obj_to_target within `radius`, margin the object's
// distance to the goal at reset.
double TowardGoal(const SawyerState& state, double obj_to_target, double radius);

// The end of Meta-World v3's reward for bringing a free object to a target,
// which push, push-back, push-wall, pick-place, pick-place-wall,
// shelf-place, hand-insert and soccer share (ObjectRewardTerms).
struct ObjectReward {
  double reward = 0;          // the shaped reward ...
  bool at_target = false;     // ... or 10 when this holds
  double obj_to_target = 0;   // info obj_to_target
  double success_radius = 0;  // success: obj_to_target within it
  double tcp_to_obj = 0;      // near_object: within near_radius
  double near_radius = 0.03;
  double grasped = 0;         // info grasp_reward
  double in_place = 0;        // info in_place_reward
  // info grasp_success; unset: GraspSuccess
  std::optional<double> grasp_success;
};
// The reward and info of `parts`.
RewardTerms ObjectRewardTerms(const SawyerState& state, const ObjectReward& parts);

// The reward and info of the tasks that grip a handle or tool and move it
// (door-open, assembly, disassemble, hammer, box-close): grasp_success once
// the grip effort `grab` reaches 0.5, grasp_reward grab, in_place_reward
// in_place, obj_to_target 0 (v3 reports none).
RewardTerms GripRewardTerms(double reward, bool success, double near_object, double grab,
                            double in_place);

// A free-object task with a static fixture that stands at the goal (a hoop,
// shelf, net, box): every reset puts the fixture body's frame at goal -
// goal_on_fixture, after placing the object.
class GoalFixtureTask : public SawyerTask {
 protected:
  GoalFixtureTask(SawyerTaskConfig config, const char* fixture_body, const Vec3& goal_on_fixture,
                  SawyerOptions options);
  void PlaceObjects(mjModel* m, mjData* d) override;

 private:
  Vec3 goal_on_fixture_;
  int fixture_ = -1;  // body
};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_OBJECT_TASKS_H_
