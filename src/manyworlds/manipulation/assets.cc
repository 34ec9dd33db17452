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

namespace {

std::vector<sim::VirtualFile> OtherAssets(std::string_view file) {
  std::vector<sim::VirtualFile> others;
  for (const EmbeddedAsset& asset : EmbeddedAssets()) {
    if (asset.name != file) others.push_back({asset.name, asset.contents});
  }
  return others;
}

}  // namespace

sim::ModelPtr LoadTaskModel(std::string_view file) {
  return sim::LoadModelFromString(FindAsset(file), OtherAssets(file), file);
}

void SaveTaskModelXml(const mjModel* model, std::string_view file, const std::string& path,
                      std::string_view extra_elements) {
  sim::SaveModelXml(model, FindAsset(file), OtherAssets(file), file, path, extra_elements);
}

}  // namespace manyworlds::manipulation
