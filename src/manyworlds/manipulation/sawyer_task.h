// SawyerTask: the shared mechanics of the Meta-World-style tasks (Meta-World
// v3's SawyerXYZEnv, sawyer_xyz_env.py): mocap-driven hand, two-finger
// gripper, the 39-value observation, reset and task variations. Each task
// derives from it, names its MJCF file and ranges (SawyerTaskConfig) and
// writes its reward.
//
// Action (4, in [-1, 1]): a[0:3] hand displacement, 1 cm per unit per step,
//   clipped to the task's hand bounds, orientation fixed; a[3] gripper
//   (-1 open .. +1 closed), sent to both finger actuators.
// Timing: 0.0025 s timestep, 5 substeps per env step, 500-step episodes
//   (truncated, never terminated).
// Observation (39):
//   [0:3]   hand position (site hand_site)
//   [3]     gripper opening = clip(|right pad - left pad| / 0.1, 0, 1)
//   [4:7]   object 1 position        [7:11]  object 1 quaternion ((x, y, z, w)
//           unless the task's config says otherwise: obj_quat)
//   [11:14] object 2 position        [14:18] object 2 quaternion (zeros when
//           the task has no second object)
//   [18:36] the previous step's [0:18] (a copy of [0:18] after reset)
//   [36:39] goal position (zeros when the goal is hidden)
//   Bounds, as v3's sawyer_observation_space: the hand in v3's _HAND_SPACE,
//   [3] in [-1, 1], objects unbounded, the goal in the task's goal_space
//   (zeros when hidden).
// Task observation: the goal position (3) when observable, else empty.
// Info: success, near_object, grasp_success, grasp_reward, in_place_reward,
//   obj_to_target, unscaled_reward (task-specific meanings; see each task).
// Task state params: {"obj_pos": [x, y, z], "goal_pos": [x, y, z]}, each
//   inside the task's ranges, xy separation >= the task's minimum.
//
// Reset: the hand is settled at the task's hand start once, at
// construction (the mocap held there for 50 env steps = 250 substeps with the
// gripper open, as Meta-World does on every reset); every reset restores that
// settled state, then places the object and goal from the task state. Resets
// are thus independent of the previous episode. The env seed has no effect:
// as in Meta-World, everything random is in the task state.
//
// MuJoCo warnings during a step (instability, full contact buffer) are
// counted (sim_warning_count, last_sim_warning); the step then reports
// reward 0 and all-zero info and truncates the episode, or, with
// throw_on_sim_warning, throws sim::SimulationWarningError.
#ifndef MANYWORLDS_MANIPULATION_SAWYER_TASK_H_
#define MANYWORLDS_MANIPULATION_SAWYER_TASK_H_

#include <array>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "manyworlds/core/env.h"
#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/reward_utils.h"
#include "manyworlds/sim/model.h"
#include "manyworlds/sim/scene_source.h"
#include "manyworlds/sim/state.h"

namespace manyworlds::manipulation {

// Observation layout.
inline constexpr int kObsSize = 39;
inline constexpr int kObsHand = 0;
inline constexpr int kObsGripper = 3;
inline constexpr int kObsObj1Pos = 4;
inline constexpr int kObsObj1Quat = 7;
inline constexpr int kObsObj2Pos = 11;
inline constexpr int kObsObj2Quat = 14;
inline constexpr int kObsFrame = 18;  // size of one frame [0:18]
inline constexpr int kObsPrev = 18;
inline constexpr int kObsGoal = 36;

inline constexpr int kFrameSkip = 5;
inline constexpr int kMaxEpisodeSteps = 500;
inline constexpr double kActionScale = 0.01;  // metres per action unit per step
// The tcp (midpoint of the finger pads) sits this far below the hand site.
inline constexpr double kTcpBelowHand = 0.035;

// How obs[7:11] holds object 1's orientation: Meta-World v3 uses, per task,
// (x, y, z, w), MuJoCo's own (w, x, y, z), or zeros.
enum class QuatLayout { kXyzw, kWxyz, kZeros };

// A box of positions, [low, high] per axis.
struct Range3 {
  Vec3 low{}, high{};
};

// Static description of one task.
struct SawyerTaskConfig {
  std::string id;           // registry id, e.g. "reach"
  std::string description;
  std::string xml_file;     // embedded asset, e.g. "reach.xml"
  Vec3 hand_low{-0.5, 0.40, 0.05};
  Vec3 hand_high{0.5, 1.0, 0.5};
  Vec3 hand_init{0.0, 0.6, 0.2};
  Vec3 obj_low, obj_high;    // object start range
  // Goal range: where goals are drawn (DeriveGoal may replace the draw) and
  // what task states' goals are checked against.
  Vec3 goal_low, goal_high;
  double min_obj_goal_xy = 0.15;   // resample while closer (xy)
  bool goal_z_at_object = false;   // goal height forced to the object's
  QuatLayout obj_quat = QuatLayout::kXyzw;  // obs[7:11]: body "obj"'s orientation
  // The body whose orientation obs[7:11] holds where v3 reads another than
  // the object point's (a fixture's fixed base); empty: body "obj".
  std::string obj_quat_body;
  // The goal's observation bounds (obs[36:39] and the task observation's
  // space): Meta-World v3's goal_space where it is not the goal range. v3
  // bounds most fixture tasks' goals by the hand's range, and widens others
  // round where their goals lie (0.1 to 1 mm, a few cm for handle-press and
  // handle-pull). Unset: [goal_low, goal_high].
  std::optional<Range3> goal_space;
};

// Task `id`'s config with the shared defaults, the object drawn from `obj`
// and the goal from `goal` (a fixture task sets the goal range from the
// object's instead: UseGoalOffset).
SawyerTaskConfig TaskConfig(std::string id, std::string description, std::string xml_file,
                            const Range3& obj, const Range3& goal = {});

// Meta-World's reward_function_version: "v2" (v3's default, rewards in
// [0, 10]) or "v1" (the original shaped rewards that Meta-World+ restored;
// unbounded, in the hundreds to thousands).
enum class RewardVersion { kV2, kV1 };

struct SawyerOptions {
  bool goal_observable = true;        // false: obs[36:39] zero, no task obs
  bool throw_on_sim_warning = false;
  RewardVersion reward_version = RewardVersion::kV2;
};

// The state record: every world-frame quantity a reward, success rule or
// info field reads, refreshed after every step. Rewards are pure functions of
// it and the action (SawyerTask::EvaluateReward), so a test can evaluate
// them on quantities read from another simulator (python: sawyer_reward).
// Meta-World v3's names for the same quantities are in brackets.
struct SawyerState {
  Vec3 hand{};       // obs[0:3], the hand position [body "hand" xpos]
  Vec3 tcp{};        // midpoint of the finger tips [tcp_center]
  Vec3 left_pad{};   // finger pads [get_body_com("leftpad"), ("rightpad")]
  Vec3 right_pad{};
  Vec3 obj{};        // obs[4:7], the task's object point [_get_pos_objects()]
  Vec3 goal{};       // [_target_pos]
  Vec3 obj_init{};   // obj at reset [obj_init_pos; stick_init_pos (stick-push, stick-pull)]
  Vec3 tcp_init{};   // tcp at reset [init_tcp]
  Vec3 hand_init{};  // the configured hand start [hand_init_pos]
  double gripper_opening = 0;  // obs[3]
  bool touching_obj = false;   // pads in contact with the object [touching_main_object]
  // peg-insert-side, stick-pull, assembly, disassemble, hammer (zeros elsewhere)
  // the peg's head [site "pegHead"]; the stick's end [site "stick_end"];
  // the nut's ring [site "RoundNut"]; the hammer's head (v1) [geom "HammerHead"]
  Vec3 obj_head{};
  Vec3 obj_head_init{};  // [peg_head_pos_init]
  // articulated tasks (zeros where a task has no such quantity)
  // The fixture joint in Meta-World's sign convention: the door hinge,
  // negative when open toward the robot [doorjoint qpos]; the lever, -pi/2
  // when pointing up [LeverAxis qpos]; the nail, driven in (hammer)
  // [NailSlideJoint qpos].
  double joint_qpos = 0;
  // The object point at reset [window_handle_pos_init (window-open,
  // window-close); _lever_pos_init (lever-pull)].
  Vec3 handle_init{};
  // Height of the object point above the goal at reset
  // [_obj_to_target_init (button-press-topdown)].
  double obj_to_target_init = 0;
  // obs[7:11], the object's orientation in the task's layout (QuatLayout)
  // [obs[7:11], _get_quat_objects()]; assembly and disassemble reward it.
  std::array<double, 4> obj_quat{};
  // Tool-use tasks (zeros elsewhere): obs[11:14], the second object's point
  // [_get_pos_objects()[3:6]: the nail (hammer), the thermos (stick-push,
  // stick-pull)], and the thermos's base frame at reset [obj_init_pos
  // (stick-push, stick-pull)].
  Vec3 obj2{};
  Vec3 obj2_init{};
  // Reward version v1 (zeros where a task's v1 reward reads none), as v3 sets
  // them at reset: the task's normaliser [maxReachDist, maxPushDist,
  // maxPullDist, maxPlacingDist or maxDist, whichever its v1 reads], the
  // object's height [objHeight] and the lift target [heightTarget].
  double v1_max_dist = 0;
  double v1_obj_height = 0;
  double v1_height_target = 0;
  // The left finger's tip [site leftEndEffector], which v1's button and
  // handle rewards read in place of the tcp. Ours is the left pad's site
  // (the same point as left_pad); in v3 it differs from the pad's centre.
  Vec3 left_finger{};
  // v1 of the tool-use tasks: the second normaliser [maxPushDist
  // (stick-push), maxPullDist (stick-pull)] and the second object's point
  // the hammer's v1 reads [site "nailHead"] (obj_head is then the hammer's
  // head [geom "HammerHead"]).
  double v1_max_dist2 = 0;
  Vec3 obj2_head{};
};

// Names of SawyerState's fields, in declaration order (the Python record's keys).
inline constexpr const char* kSawyerStateFields[] = {
    "hand",     "tcp",      "left_pad",  "right_pad",       "obj",         "goal",
    "obj_init", "tcp_init", "hand_init", "gripper_opening", "touching_obj",
    "obj_head", "obj_head_init",
    "joint_qpos", "handle_init", "obj_to_target_init",  // articulated tasks
    "obj_quat",
    "obj2", "obj2_init",  // tool-use tasks
    "v1_max_dist", "v1_obj_height", "v1_height_target", "left_finger",  // reward version v1
    "v1_max_dist2", "obj2_head"};

// One step's reward and info values.
struct RewardTerms {
  double reward = 0;  // in [0, 10] (v2); v1's are unbounded
  bool success = false;
  double near_object = 0;
  double grasp_success = 0;
  double grasp_reward = 0;
  double in_place_reward = 0;
  double obj_to_target = 0;
};

class SawyerTask : public Env, public sim::SceneSource, public ScriptedPolicySource {
 public:
  const mjModel* model() const { return model_.get(); }
  const mjData* data() const { return data_.get(); }
  const SawyerTaskConfig& config() const { return config_; }
  const SawyerState& state() const { return state_; }
  // The reward and info this task computes for any state record, as a step
  // does from the simulator's. `action` has 4 values; like Step, the
  // gripper value is clipped to [-1, 1]. Throws Error on a wrong size or a
  // non-finite value.
  // The env's reward version (SawyerOptions) decides which reward.
  RewardTerms EvaluateReward(const SawyerState& state, std::span<const float> action) const;
  RewardVersion reward_version() const { return options_.reward_version; }
  long sim_warning_count() const { return sim_warning_count_; }

  // Writes the complete MJCF of the current variation (objects, fixtures,
  // goal marker and hand target where a reset puts them) to `path`; MuJoCo
  // loads it on its own. Its keyframe "reset" holds the complete state after
  // a reset (arm at the hand start, fixtures at their start angles):
  // mj_resetDataKeyframe(m, d, 0) restores it. Throws EpisodeStateError
  // before a task is set, sim::MujocoError if writing fails.
  void SaveVariationXml(const std::string& path) const;
  const std::string& last_sim_warning() const { return last_sim_warning_; }

  // SceneSource: the task's own model and data; the MJCF is
  // SaveVariationXml's.
  sim::Scene ActiveScene() const override { return {model(), data()}; }
  void SaveSceneXml(const std::string& path) const override { SaveVariationXml(path); }
  // ScriptedPolicySource: the task's scripted policy, privileged (it reads
  // the true goal, so it also acts when the goal is hidden). Defined in
  // benchmark.cc, next to the policy it shares with Benchmark.
  std::unique_ptr<Policy> CreateScriptedPolicy() const override;

 protected:
  SawyerTask(SawyerTaskConfig config, SawyerOptions options);

  // The task's reward and info for the state after a step. Pure.
  virtual RewardTerms ComputeReward(const SawyerState& state,
                                    std::span<const float> action) const = 0;
  // The same under reward version v1 (Meta-World's original shaped
  // reward; reward_v1.h has the shared pieces). Pure.
  virtual RewardTerms ComputeRewardV1(const SawyerState& state,
                                      std::span<const float> action) const = 0;

  TaskState DoSampleTaskState(Rng& task_rng) override;
  TaskState DoGetTaskState() const override;
  void DoSetTaskState(const TaskState& state) override;
  void DoReset(const ObsView& out) override;
  void DoStep(std::span<const float> action, const StepView& out) override;

  // Hooks for tasks whose objects are not one free body (fixtures such as
  // doors and drawers, a second object). The defaults serve the free body
  // "obj" of reach, push and pick-place.

  // The goal that belongs to an object position and a goal drawn from
  // [goal_low, goal_high]. Default: the drawn goal, at the object's height
  // with goal_z_at_object. A task whose goal is fixed relative to a fixture
  // returns obj + offset (and sets min_obj_goal_xy to 0). set_task_state
  // rejects goals that are not their own DeriveGoal.
  virtual Vec3 DeriveGoal(const Vec3& obj, const Vec3& drawn_goal) const;
  // Puts the objects in place for the current variation (obj_pos(),
  // goal_pos()); called at reset after the settled state is restored, before
  // mj_forward. Default: the free body "obj" upright and at rest at
  // obj_pos(). A fixture may move its own body in the model (m->body_pos):
  // every env owns its model.
  virtual void PlaceObjects(mjModel* m, mjData* d);
  // Task-specific fields of the state record, and a task's own object
  // point (state.obj, obs[4:7]) where it is not the body "obj"'s origin;
  // called after every reset and step once the shared fields are set.
  virtual void RefreshTaskState(const mjData* /*d*/, SawyerState& /*state*/) const {}
  // Task-specific values of the record's "at reset" fields, called at reset
  // after the record is refreshed and obj_init (= obj_pos()) and tcp_init
  // are set.
  virtual void InitTaskState(SawyerState& /*state*/) const {}
  // obs[11:18]: position and (x, y, z, w) quaternion of a second object.
  // Default: zeros (no second object).
  virtual void WriteObject2(const mjData* d, float* pos_quat) const;

  const Vec3& obj_pos() const { return obj_pos_; }
  const Vec3& goal_pos() const { return goal_pos_; }

 private:
  static EnvSpec MakeSpec(const SawyerTaskConfig& config, const SawyerOptions& options);
  void RefreshState();
  void WriteFrame(float* frame) const;  // the 18 values of obs[0:18]
  void WriteObs(std::span<float> obs) const;

  SawyerTaskConfig config_;
  SawyerOptions options_;
  sim::ModelPtr model_;
  sim::DataPtr data_;
  sim::SimState settled_;  // hand settled at hand_init, gripper open

  // Ids cached at construction.
  int hand_site_ = -1, left_pad_site_ = -1, right_pad_site_ = -1;
  int obj_body_ = -1, obj_geom_ = -1, left_pad_geom_ = -1, right_pad_geom_ = -1;
  int obj_qpos_ = -1, obj_dof_ = -1;  // -1: "obj" has no free joint
  int obj_quat_body_ = -1;  // obs[7:11]'s body
  int hand_mocap_ = -1, goal_mocap_ = -1;
  int left_act_ = -1, right_act_ = -1;

  Vec3 obj_pos_{}, goal_pos_{};  // the task variation
  SawyerState state_;
  float prev_frame_[kObsFrame] = {};
  long sim_warning_count_ = 0;
  std::string last_sim_warning_;
};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_SAWYER_TASK_H_
