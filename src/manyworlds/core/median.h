// The median of a sample (the mean of the two middle values of an even count), as every
// benchmark of this project reports its repeats.
#ifndef MANYWORLDS_CORE_MEDIAN_H_
#define MANYWORLDS_CORE_MEDIAN_H_

#include <algorithm>
#include <stdexcept>
#include <vector>

namespace manyworlds {

inline double Median(std::vector<double> values) {
  if (values.empty()) throw std::invalid_argument("the median of no values");
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

}  // namespace manyworlds

#endif  // MANYWORLDS_CORE_MEDIAN_H_
