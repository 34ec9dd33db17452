// Named scalar results of an update (losses, temperatures, means). Agents
// return them and never log; the caller decides where they go.
#ifndef MANYWORLDS_AGENTS_METRICS_H_
#define MANYWORLDS_AGENTS_METRICS_H_

#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace manyworlds::agents {

// A small ordered map of doubles; insertion order is kept for printing.
class Metrics {
 public:
  // Sets (or overwrites) a value.
  void Set(std::string_view name, double value);
  std::optional<double> Find(std::string_view name) const;
  // Throws Error naming the known metrics if `name` is absent.
  double Get(std::string_view name) const;
  bool Contains(std::string_view name) const { return Find(name).has_value(); }

  const std::vector<std::pair<std::string, double>>& items() const { return items_; }
  size_t size() const { return items_.size(); }

 private:
  std::vector<std::pair<std::string, double>> items_;
};

}  // namespace manyworlds::agents

#endif  // MANYWORLDS_AGENTS_METRICS_H_
