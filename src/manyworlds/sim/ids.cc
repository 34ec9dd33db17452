#include "manyworlds/sim/ids.h"

#include "manyworlds/sim/mujoco_error.h"

namespace manyworlds::sim {

IdLookup::IdLookup(const mjModel* model, std::string model_name)
    : model_(model), model_name_(std::move(model_name)) {
  if (model_ == nullptr) throw MujocoError("IdLookup for '" + model_name_ + "': model is null");
}

int IdLookup::FindOptional(mjtObj type, std::string_view name) const {
  return mj_name2id(model_, type, std::string(name).c_str());
}

int IdLookup::Find(mjtObj type, const char* kind, std::string_view name) const {
  const int id = FindOptional(type, name);
  if (id < 0) {
    throw MujocoError("model '" + model_name_ + "' has no " + kind + " named '" +
                      std::string(name) + "'");
  }
  return id;
}

int IdLookup::MocapIndex(std::string_view body) const {
  const int id = Body(body);
  const int index = model_->body_mocapid[id];
  if (index < 0) {
    throw MujocoError("model '" + model_name_ + "': body '" + std::string(body) +
                      "' is not a mocap body");
  }
  return index;
}

int IdLookup::FreeJointQposAddress(std::string_view body) const {
  const int id = Body(body);
  if (model_->body_jntnum[id] < 1 || model_->jnt_type[model_->body_jntadr[id]] != mjJNT_FREE) {
    throw MujocoError("model '" + model_name_ + "': body '" + std::string(body) +
                      "' has no free joint");
  }
  return model_->jnt_qposadr[model_->body_jntadr[id]];
}

}  // namespace manyworlds::sim
