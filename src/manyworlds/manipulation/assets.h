// The manipulation MJCF files, compiled into the library (see
// embed_assets.cmake), and loading a task model from them.
#ifndef MANYWORLDS_MANIPULATION_ASSETS_H_
#define MANYWORLDS_MANIPULATION_ASSETS_H_

#include <span>
#include <string>
#include <string_view>

#include "manyworlds/sim/model.h"

namespace manyworlds::manipulation {

struct EmbeddedAsset {
  std::string_view name;      // file name, e.g. "reach.xml"
  std::string_view contents;  // the file's text
};

// Every file under src/manyworlds/manipulation/assets/.
std::span<const EmbeddedAsset> EmbeddedAssets();

// The text of one asset; throws Error listing the available names.
std::string_view FindAsset(std::string_view name);

// Compiles the named task file; the other assets are visible to its
// <include> elements. Throws sim::MujocoError.
sim::ModelPtr LoadTaskModel(std::string_view file);

// Writes `model` (compiled from `file`, possibly with moved bodies) as one
// self-contained MJCF file at `path`, with `extra_elements` (e.g. a
// keyframe) before </mujoco>. Throws sim::MujocoError.
void SaveTaskModelXml(const mjModel* model, std::string_view file, const std::string& path,
                      std::string_view extra_elements = {});

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_ASSETS_H_
