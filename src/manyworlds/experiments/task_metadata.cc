#include "manyworlds/experiments/task_metadata.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <vector>

#include "manyworlds/core/error.h"

namespace manyworlds::experiments {
namespace {

// Far above any embedding file (50 tasks x 4,096 numbers is ~2 MB).
constexpr std::uintmax_t kMaxBytes = 64u << 20;
constexpr size_t kMaxDim = 65536;

}  // namespace

torch::Tensor LoadTaskMetadata(const std::string& path, const TaskSet& tasks) {
  const std::string where = "agent.task_metadata '" + path + "'";
  std::error_code ec;
  const std::uintmax_t bytes = std::filesystem::file_size(path, ec);
  if (ec) {
    const std::filesystem::path p(path);
    throw ConfigError(where + ": cannot read it (" + ec.message() + ")" +
                      (p.is_relative() ? "; a relative path is read from the current directory, " +
                                             std::filesystem::current_path().string()
                                       : std::string()));
  }
  if (bytes > kMaxBytes) {
    throw ConfigError(where + ": " + std::to_string(bytes) + " bytes; at most " +
                      std::to_string(kMaxBytes) + " are read");
  }
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  if (!in.good() && !in.eof()) throw ConfigError(where + ": cannot read it");
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(text.str());
  } catch (const nlohmann::json::parse_error& e) {
    throw ConfigError(where + ": not JSON (" + std::string(e.what()) + ")");
  }
  if (!doc.is_object() || !doc.contains("tasks") || !doc["tasks"].is_object()) {
    throw ConfigError(where + ": needs a \"tasks\" object mapping task names to "
                      "{\"embedding\": [numbers]}");
  }
  const nlohmann::json& table = doc["tasks"];
  std::vector<float> values;
  size_t dim = 0;
  for (const TaskSpec& task : tasks.tasks) {
    if (!table.contains(task.name)) {
      std::string some;
      int listed = 0;
      for (auto it = table.begin(); it != table.end() && listed < 5; ++it, ++listed) {
        some += (some.empty() ? "" : ", ") + it.key();
      }
      throw ConfigError(where + ": no vector for task '" + task.name + "' (it has " +
                        std::to_string(table.size()) + " tasks: " + some +
                        (table.size() > 5 ? ", ..." : "") + ")");
    }
    const nlohmann::json& entry = table[task.name];
    const nlohmann::json* vector = entry.is_object() && entry.contains("embedding")
                                       ? &entry["embedding"]
                                       : &entry;  // a bare list is accepted too
    if (!vector->is_array() || vector->empty() || vector->size() > kMaxDim) {
      throw ConfigError(where + ": task '" + task.name + "' needs a list of 1 to " +
                        std::to_string(kMaxDim) + " numbers");
    }
    if (dim == 0) dim = vector->size();
    if (vector->size() != dim) {
      throw ConfigError(where + ": task '" + task.name + "' has " +
                        std::to_string(vector->size()) + " numbers, the first task " +
                        std::to_string(dim));
    }
    for (const nlohmann::json& x : *vector) {
      if (!x.is_number() || !std::isfinite(x.get<double>())) {
        throw ConfigError(where + ": task '" + task.name + "' has a value that is not a "
                          "finite number");
      }
      values.push_back(x.get<float>());
    }
  }
  return torch::from_blob(values.data(),
                          {static_cast<int64_t>(tasks.tasks.size()), static_cast<int64_t>(dim)},
                          torch::kFloat32)
      .clone();
}

}  // namespace manyworlds::experiments
