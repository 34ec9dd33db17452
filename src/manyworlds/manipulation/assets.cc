#include "manyworlds/manipulation/assets.h"

#include <string>
#include <vector>

#include "manyworlds/core/error.h"

namespace manyworlds::manipulation {

std::string_view FindAsset(std::string_view name) {
  std::string names;
  for (const EmbeddedAsset& asset : EmbeddedAssets()) {
    if (asset.name == name) return asset.contents;
    names += (names.empty() ? "" : ", ") + std::string(asset.name);
  }
  throw Error("no manipulation asset named '" + std::string(name) + "' (available: " + names + ")");
}

sim::ModelPtr LoadTaskModel(std::string_view file) {
  const std::string_view main = FindAsset(file);
  std::vector<sim::VirtualFile> others;
  for (const EmbeddedAsset& asset : EmbeddedAssets()) {
    if (asset.name != file) others.push_back({asset.name, asset.contents});
  }
  return sim::LoadModelFromString(main, others, file);
}

}  // namespace manyworlds::manipulation
