// Name -> id lookups done once, with errors that name what is missing.
//
//   sim::IdLookup ids(model, "reach");
//   const int hand = ids.Body("hand");   // throws MujocoError if absent
//
// Look ids up at construction and keep the ints; never call mj_name2id in a
// step.
#ifndef MANYWORLDS_SIM_IDS_H_
#define MANYWORLDS_SIM_IDS_H_

#include <string>
#include <string_view>

#include <mujoco/mujoco.h>

namespace manyworlds::sim {

class IdLookup {
 public:
  // `model` must outlive the lookup; `model_name` is used in messages.
  IdLookup(const mjModel* model, std::string model_name);

  int Body(std::string_view name) const { return Find(mjOBJ_BODY, "body", name); }
  int Site(std::string_view name) const { return Find(mjOBJ_SITE, "site", name); }
  int Geom(std::string_view name) const { return Find(mjOBJ_GEOM, "geom", name); }
  int Joint(std::string_view name) const { return Find(mjOBJ_JOINT, "joint", name); }
  int Actuator(std::string_view name) const { return Find(mjOBJ_ACTUATOR, "actuator", name); }
  int Equality(std::string_view name) const { return Find(mjOBJ_EQUALITY, "equality", name); }

  // Index into mjData::mocap_pos/mocap_quat of a mocap body.
  int MocapIndex(std::string_view body) const;
  // Addresses in qpos / qvel of a joint.
  int QposAddress(std::string_view joint) const { return model_->jnt_qposadr[Joint(joint)]; }
  int DofAddress(std::string_view joint) const { return model_->jnt_dofadr[Joint(joint)]; }
  // Address in qpos of a body's free joint (its first joint must be free).
  int FreeJointQposAddress(std::string_view body) const;

  // -1 instead of an error, for optional elements.
  int FindOptional(mjtObj type, std::string_view name) const;

 private:
  int Find(mjtObj type, const char* kind, std::string_view name) const;

  const mjModel* model_;
  std::string model_name_;
};

}  // namespace manyworlds::sim

#endif  // MANYWORLDS_SIM_IDS_H_
