// Mean of each learner metric over an iteration's updates, in first-seen order.
#ifndef MANYWORLDS_EXPERIMENTS_METRIC_MEANS_H_
#define MANYWORLDS_EXPERIMENTS_METRIC_MEANS_H_

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "manyworlds/agents/metrics.h"

namespace manyworlds::experiments {

class MetricMeans {
 public:
  void Add(const agents::Metrics& m) {
    for (const auto& [name, value] : m.items()) {
      auto it = std::find_if(sums_.begin(), sums_.end(),
                             [&](const auto& s) { return s.first == name; });
      if (it == sums_.end()) {
        sums_.emplace_back(name, 0.0);
        counts_.push_back(0);
        it = sums_.end() - 1;
      }
      it->second += value;
      ++counts_[it - sums_.begin()];
    }
  }
  void WriteTo(nlohmann::json& row) const {
    for (size_t i = 0; i < sums_.size(); ++i) row[sums_[i].first] = sums_[i].second / counts_[i];
  }

 private:
  std::vector<std::pair<std::string, double>> sums_;
  std::vector<int64_t> counts_;
};

}  // namespace manyworlds::experiments

#endif  // MANYWORLDS_EXPERIMENTS_METRIC_MEANS_H_
