// RAII owners for mjModel / mjData and model loading.
//
//   sim::ModelPtr model = sim::LoadModelFromString(xml);   // throws MujocoError
//   sim::DataPtr data = sim::MakeData(model.get());
//
// Loading never aborts the process: MuJoCo's parse and compile errors, and
// any mju_error raised meanwhile, become MujocoError carrying MuJoCo's text.
#ifndef MANYWORLDS_SIM_MODEL_H_
#define MANYWORLDS_SIM_MODEL_H_

#include <memory>
#include <span>
#include <string>
#include <string_view>

#include <mujoco/mujoco.h>

#include "manyworlds/sim/mujoco_error.h"

namespace manyworlds::sim {

struct ModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
struct DataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};
using ModelPtr = std::unique_ptr<mjModel, ModelDeleter>;
using DataPtr = std::unique_ptr<mjData, DataDeleter>;

// An in-memory file made visible to the XML loader (for <include file=...>,
// meshes, ...). Both views must outlive the load call only.
struct VirtualFile {
  std::string_view name;      // file name without directory
  std::string_view contents;
};

// Compiles an MJCF document held in memory. `main_name` is the name the
// document gets in the loader's virtual file system (and in messages);
// `files` are other documents it may include by name. Throws MujocoError.
ModelPtr LoadModelFromString(std::string_view xml, std::span<const VirtualFile> files = {},
                             std::string_view main_name = "model.xml");

// Compiles an MJCF (or binary MJB, by extension) file from disk. Throws
// MujocoError naming the path.
ModelPtr LoadModelFromFile(const std::string& path);

// Writes `model` as one self-contained MJCF file (includes expanded) to
// `path`, atomically. MuJoCo can only save the model it compiled last, so
// this compiles `xml` (with `files`) again and, under the loading lock,
// saves it with the numeric values of `model` (which must come from the same
// document; e.g. a copy with moved bodies). `extra_elements`, if given, is
// MJCF inserted before the closing </mujoco> tag (e.g. KeyframeXml).
// Throws MujocoError.
void SaveModelXml(const mjModel* model, std::string_view xml, std::span<const VirtualFile> files,
                  std::string_view main_name, const std::string& path,
                  std::string_view extra_elements = {});

// A <keyframe> element with one key `name` holding the state in `data`
// (qpos, qvel, act, ctrl, mocap pose as MuJoCo 2.2's mpos/mquat), printed exactly (17 digits), so that
// mj_resetDataKeyframe on the saved model restores that state. The model
// must have no keyframes of its own.
std::string KeyframeXml(const mjModel* model, const mjData* data, std::string_view name);

// Allocates data for a model (non-null). Throws MujocoError.
DataPtr MakeData(const mjModel* model);

}  // namespace manyworlds::sim

#endif  // MANYWORLDS_SIM_MODEL_H_
