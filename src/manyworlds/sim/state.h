// Snapshots of the mutable simulation state, for determinism tests and for
// restoring a settled start state cheaply.
//
// A SimState holds everything mj_step reads from mjData that a user or a
// previous step sets: time, qpos, qvel, act, ctrl, mocap pose and the
// solver's warm start (without it, a restored state would step differently
// from the original by solver tolerance).
#ifndef MANYWORLDS_SIM_STATE_H_
#define MANYWORLDS_SIM_STATE_H_

#include <vector>

#include <mujoco/mujoco.h>

namespace manyworlds::sim {

struct SimState {
  mjtNum time = 0;
  std::vector<mjtNum> qpos;            // (nq)
  std::vector<mjtNum> qvel;            // (nv)
  std::vector<mjtNum> act;             // (na)
  std::vector<mjtNum> ctrl;            // (nu)
  std::vector<mjtNum> mocap_pos;       // (nmocap x 3)
  std::vector<mjtNum> mocap_quat;      // (nmocap x 4)
  std::vector<mjtNum> qacc_warmstart;  // (nv)

  bool operator==(const SimState& other) const = default;
};

// Copies the state out of `data`. The overload with an output reuses its
// buffers (no allocation once they have the right sizes).
SimState GetState(const mjModel* model, const mjData* data);
void GetState(const mjModel* model, const mjData* data, SimState* out);

// Writes a state into `data`. Throws MujocoError if its sizes do not match
// the model. Does not call mj_forward: derived quantities (xpos, contacts)
// are stale until the caller runs it or steps.
void SetState(const mjModel* model, mjData* data, const SimState& state);

// Largest absolute difference over all fields (inf if the sizes differ).
double MaxAbsDifference(const SimState& a, const SimState& b);

}  // namespace manyworlds::sim

#endif  // MANYWORLDS_SIM_STATE_H_
