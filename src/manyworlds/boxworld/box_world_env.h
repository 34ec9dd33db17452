// The box world env (docs/boxworld.md): an agent on a walled floor reaches a
// target (simple task) or pushes every box to it (complex task), in worlds
// drawn by the generator of boxworld/world.h. The task state is the whole
// world (WorldParams as JSON), so one env id covers a fixed layout with
// varying targets and worlds where everything varies.
//
//   action:   Box(-1, 1, (3,)): force along world x and y and torque about z,
//             as fractions of agent_force and agent_torque (ctrl = action x
//             the actuator's ctrl range).
//   env_obs:  Box(-inf, inf, (8 + 9 max_boxes,)):
//               [0]      floor_size
//               [1, 2]   agent x, y
//               [3, 4]   cos, sin of the agent's heading
//               [5, 6]   agent velocity x, y
//               [7]      agent turn rate
//             then per box slot k < max_boxes, at 8 + 9k:
//               [+0]     mask: 1 if the world has box k, else 0 (and the
//                        slot's other values are 0)
//               [+1..3]  position x, y, z
//               [+4..7]  orientation quaternion w, x, y, z
//               [+8]     1 once the box has been delivered (complex task)
//             with target_in_obs, two more values at 8 + 9 max_boxes: the
//             target x, y (zeros if hide_target), for learners that read
//             env_obs only (the trainer's policies).
//   task_obs: Box(2,): the target x, y; zeros if hide_target.
//   reward:   simple:  -0.001 d(agent, target) per step; a step that ends
//                      with d < success_radius pays +100 instead and
//                      terminates.
//             complex: -0.001 x the sum of d(box, target) over the boxes not
//                      yet delivered after the step, +100 for each box whose
//                      d drops below success_radius for the first time (it
//                      is then delivered for good and leaves the sum);
//                      terminates when every box is delivered.
//             Distances are in the floor plane (x, y).
//   end:      truncated after 1024 steps (max_episode_steps).
//   info:     success (simple: the target was reached; complex: every box
//             delivered), boxes_delivered, distance (the summed distance the
//             reward penalises), sim_warnings.
//   MuJoCo warnings end the episode (truncated, reward 0) and are counted in
//   sim_warnings, or throw with throw_on_sim_warning.
//
// Everything random is in the task state: reset is deterministic
// (spec().uses_env_seed is false). A model is compiled only when a new task
// state changes the world's structure (floor, walls, agent, boxes); a new
// target or new start positions reuse the model.
#ifndef MANYWORLDS_BOXWORLD_BOX_WORLD_ENV_H_
#define MANYWORLDS_BOXWORLD_BOX_WORLD_ENV_H_

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "manyworlds/boxworld/world.h"
#include "manyworlds/core/env.h"
#include "manyworlds/core/policy.h"
#include "manyworlds/sim/model.h"
#include "manyworlds/sim/scene_source.h"

namespace manyworlds::boxworld {

enum class BoxTask { kSimple, kComplex };

inline constexpr int64_t kEpisodeSteps = 1024;
inline constexpr double kDistanceCost = 0.001;
inline constexpr double kSuccessBonus = 100.0;
inline constexpr int kAgentObs = 8;
inline constexpr int kBoxObs = 9;

class BoxWorldEnv : public Env, public sim::SceneSource, public ScriptedPolicySource {
 public:
  struct Config {
    BoxTask task = BoxTask::kSimple;
    WorldDistribution distribution = {};
    int max_boxes = 8;  // observation slots, in [1, kMaxBoxesLimit]
    bool hide_target = false;
    // Append the target x, y to env_obs (the study's observation holds it).
    bool target_in_obs = false;
    // > 1: groups of this many consecutive task draws (after SeedTask) share
    // one layout drawn from the task generator, and only the target varies
    // within a group (the study's support and query tasks of one round).
    // Needs distribution.layout_seed = -1.
    int64_t targets_per_layout = 1;
    bool throw_on_sim_warning = false;
  };

  // Throws ConfigError for bad options (distribution ranges, max_boxes
  // below the largest num_boxes, a complex task without boxes, or ranges
  // that validate but leave no room for a target in one of 8 probe worlds).
  explicit BoxWorldEnv(const Config& config);

  static const char* IdOf(BoxTask task);
  // Also restarts the layout groups of targets_per_layout.
  void SeedTask(uint64_t seed) override;
  const Config& config() const { return config_; }
  // The current world (valid once a task is set).
  const WorldParams& world() const { return world_; }
  const mjModel* model() const { return model_.get(); }
  const mjData* data() const { return data_.get(); }
  // Models compiled so far (a new structure each; for tests and benchmarks).
  int64_t models_built() const { return models_built_; }
  // Whether box i has been delivered in the running episode.
  bool delivered(size_t i) const { return delivered_[i] != 0; }

  // SceneSource: the current world's model and data (none before the first
  // task state), and its MJCF (WorldMjcf).
  sim::Scene ActiveScene() const override;
  void SaveSceneXml(const std::string& path) const override;
  // world_model.h's cameras, in every generated world.
  std::vector<std::string> scene_cameras() const override {
    return {"top", "perspective", "front"};
  }
  // ScriptedPolicySource: scripted_policy.h's policy.
  std::unique_ptr<Policy> CreateScriptedPolicy() const override;

 protected:
  TaskState DoSampleTaskState(Rng& task_rng) override;
  TaskState DoGetTaskState() const override;
  void DoSetTaskState(const TaskState& state) override;
  void DoReset(const ObsView& out) override;
  void DoStep(std::span<const float> action, const StepView& out) override;

 private:
  static EnvSpec MakeSpec(const Config& config);
  void CacheIds();
  void WriteObs(std::span<float> out) const;
  double PlanarDistance(int qpos_address) const;
  // Boxes outside the walls or under the floor after a step (counted as
  // simulation warnings); throws SimulationWarningError with
  // throw_on_sim_warning.
  int BoxesOutsideTheArena() const;

  Config config_;
  WorldParams world_;
  sim::ModelPtr model_;
  sim::DataPtr data_;
  int64_t models_built_ = 0;
  // qpos/qvel addresses
  int agent_qpos_ = 0;  // x, y, yaw consecutive
  int agent_qvel_ = 0;
  std::vector<int> box_qpos_;  // free joint: x y z qw qx qy qz
  int target_site_ = -1;
  std::vector<double> ctrl_scale_;  // upper ctrl range of each actuator
  std::vector<uint8_t> delivered_;
  bool reached_ = false;
  int64_t draws_ = 0;          // task draws since SeedTask (targets_per_layout)
  int64_t group_layout_ = -1;  // layout seed of the current group
};

}  // namespace manyworlds::boxworld

#endif  // MANYWORLDS_BOXWORLD_BOX_WORLD_ENV_H_
