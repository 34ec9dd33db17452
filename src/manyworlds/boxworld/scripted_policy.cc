#include "manyworlds/boxworld/scripted_policy.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace manyworlds::boxworld {
namespace {

// The scripted policy (see scripted_policy.h).
class ScriptedPolicy : public Policy {
 public:
  explicit ScriptedPolicy(const BoxWorldEnv& env) : env_(env) {}

  void Act(std::span<const float>, std::span<const float>, std::span<float> action) override {
    const WorldParams& w = env_.world();
    const mjData* d = env_.data();
    const mjModel* m = env_.model();
    const int agent = m->jnt_qposadr[mj_name2id(m, mjOBJ_JOINT, "agent_x")];
    const int agent_v = m->jnt_dofadr[mj_name2id(m, mjOBJ_JOINT, "agent_x")];
    const Vec2 p = {d->qpos[agent], d->qpos[agent + 1]};
    const Vec2 v = {d->qvel[agent_v], d->qvel[agent_v + 1]};
    Vec2 goal = w.target;
    const bool complex = env_.config().task == BoxTask::kComplex;
    for (size_t k = 0; complex && k < w.boxes.size(); ++k) {
      if (env_.delivered(k)) continue;
      const int q = m->jnt_qposadr[mj_name2id(m, mjOBJ_JOINT, ("box" + std::to_string(k)).c_str())];
      goal = PushGoal(w, {d->qpos[q], d->qpos[q + 1]}, FootprintRadius(w.boxes[k]), p);
      break;
    }
    constexpr double kGain = 3.0, kDamping = 0.6;
    for (int i = 0; i < 2; ++i) {
      action[i] = static_cast<float>(std::clamp(kGain * (goal[i] - p[i]) - kDamping * v[i], -1.0, 1.0));
    }
    action[2] = static_cast<float>(std::clamp(-d->qvel[agent_v + 2], -1.0, 1.0));
  }

 private:
  // Where the agent heads to push the box at `b` (footprint radius rho)
  // toward the target.
  static Vec2 PushGoal(const WorldParams& w, const Vec2& b, double rho, const Vec2& p) {
    Vec2 u = {w.target[0] - b[0], w.target[1] - b[1]};
    const double len = std::max(std::hypot(u[0], u[1]), 1e-9);
    u = {u[0] / len, u[1] / len};
    const Vec2 rel = {p[0] - b[0], p[1] - b[1]};
    const double along = rel[0] * u[0] + rel[1] * u[1];
    const Vec2 lateral = {rel[0] - along * u[0], rel[1] - along * u[1]};
    const double lat = std::hypot(lateral[0], lateral[1]);
    const double contact = rho + w.agent_radius;
    if (along < -0.6 * contact && lat < 0.35 * rho + 0.02) {
      // behind the box and on the line: push through it, steering back to
      // the line
      return {b[0] + 0.8 * u[0] - 1.5 * lateral[0], b[1] + 0.8 * u[1] - 1.5 * lateral[1]};
    }
    if (along > -0.5 * contact && lat < contact + 0.15) {
      // beside or in front: go round on the agent's side
      Vec2 n = lat > 1e-6 ? Vec2{lateral[0] / lat, lateral[1] / lat} : Vec2{-u[1], u[0]};
      return {b[0] + n[0] * (contact + 0.3) - u[0] * 0.5 * contact,
              b[1] + n[1] * (contact + 0.3) - u[1] * 0.5 * contact};
    }
    return {b[0] - u[0] * (contact + 0.08), b[1] - u[1] * (contact + 0.08)};
  }

  const BoxWorldEnv& env_;
};

}  // namespace

std::unique_ptr<Policy> MakeScriptedPolicy(const BoxWorldEnv& env) {
  return std::make_unique<ScriptedPolicy>(env);
}

}  // namespace manyworlds::boxworld
