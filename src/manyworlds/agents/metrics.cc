#include "manyworlds/agents/metrics.h"

#include "manyworlds/core/error.h"

namespace manyworlds::agents {

void Metrics::Set(std::string_view name, double value) {
  for (auto& [key, old] : items_) {
    if (key == name) {
      old = value;
      return;
    }
  }
  items_.emplace_back(std::string(name), value);
}

std::optional<double> Metrics::Find(std::string_view name) const {
  for (const auto& [key, value] : items_) {
    if (key == name) return value;
  }
  return std::nullopt;
}

double Metrics::Get(std::string_view name) const {
  if (std::optional<double> value = Find(name)) return *value;
  std::string known;
  for (const auto& item : items_) known += (known.empty() ? "" : ", ") + item.first;
  throw Error("no metric '" + std::string(name) + "' (have: " + known + ")");
}

}  // namespace manyworlds::agents
