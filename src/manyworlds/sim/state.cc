#include "manyworlds/sim/state.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "manyworlds/sim/mujoco_error.h"

namespace manyworlds::sim {
namespace {

void CopyOut(const mjtNum* src, int n, std::vector<mjtNum>* out) {
  out->resize(n);
  std::copy(src, src + n, out->begin());
}

void CopyIn(const std::vector<mjtNum>& src, int n, mjtNum* dst, const char* field) {
  if (static_cast<int>(src.size()) != n) {
    throw MujocoError(std::string("SetState: field '") + field + "' has " +
                      std::to_string(src.size()) + " values, the model needs " + std::to_string(n));
  }
  std::copy(src.begin(), src.end(), dst);
}

double MaxDiff(const std::vector<mjtNum>& a, const std::vector<mjtNum>& b) {
  if (a.size() != b.size()) return std::numeric_limits<double>::infinity();
  double worst = 0;
  for (size_t i = 0; i < a.size(); ++i) worst = std::max(worst, std::abs(a[i] - b[i]));
  return worst;
}

}  // namespace

void GetState(const mjModel* m, const mjData* d, SimState* out) {
  out->time = d->time;
  CopyOut(d->qpos, m->nq, &out->qpos);
  CopyOut(d->qvel, m->nv, &out->qvel);
  CopyOut(d->act, m->na, &out->act);
  CopyOut(d->ctrl, m->nu, &out->ctrl);
  CopyOut(d->mocap_pos, 3 * m->nmocap, &out->mocap_pos);
  CopyOut(d->mocap_quat, 4 * m->nmocap, &out->mocap_quat);
  CopyOut(d->qacc_warmstart, m->nv, &out->qacc_warmstart);
}

SimState GetState(const mjModel* m, const mjData* d) {
  SimState state;
  GetState(m, d, &state);
  return state;
}

void SetState(const mjModel* m, mjData* d, const SimState& s) {
  CopyIn(s.qpos, m->nq, d->qpos, "qpos");
  CopyIn(s.qvel, m->nv, d->qvel, "qvel");
  CopyIn(s.act, m->na, d->act, "act");
  CopyIn(s.ctrl, m->nu, d->ctrl, "ctrl");
  CopyIn(s.mocap_pos, 3 * m->nmocap, d->mocap_pos, "mocap_pos");
  CopyIn(s.mocap_quat, 4 * m->nmocap, d->mocap_quat, "mocap_quat");
  CopyIn(s.qacc_warmstart, m->nv, d->qacc_warmstart, "qacc_warmstart");
  d->time = s.time;
}

double MaxAbsDifference(const SimState& a, const SimState& b) {
  double worst = std::abs(a.time - b.time);
  for (auto field : {&SimState::qpos, &SimState::qvel, &SimState::act, &SimState::ctrl,
                     &SimState::mocap_pos, &SimState::mocap_quat, &SimState::qacc_warmstart}) {
    worst = std::max(worst, MaxDiff(a.*field, b.*field));
  }
  return worst;
}

}  // namespace manyworlds::sim
