// Any text: ParseYaml returns a tree or throws ConfigError, never anything
// else; a tree dumps to YAML that parses back to the same tree.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "manyworlds/config/yaml.h"
#include "manyworlds/core/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  nlohmann::json tree;
  try {
    tree = manyworlds::ParseYaml(text);
  } catch (const manyworlds::ConfigError&) {
    return 0;
  }
  const std::string dumped = manyworlds::DumpYaml(tree);
  // NaN never equals itself: compare the dumps instead of the trees
  if (manyworlds::DumpYaml(manyworlds::ParseYaml(dumped)) != dumped) std::abort();
  return 0;
}
