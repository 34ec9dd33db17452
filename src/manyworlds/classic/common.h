// Helpers shared by the classic envs: option range checks that raise
// ConfigError with the env id, the option and the allowed range.
#ifndef MANYWORLDS_CLASSIC_COMMON_H_
#define MANYWORLDS_CLASSIC_COMMON_H_

#include <cstdint>
#include <limits>
#include <string_view>

namespace manyworlds::classic {

inline constexpr int64_t kNoUpperLimit = std::numeric_limits<int64_t>::max();

// Returns value, or throws ConfigError if it lies outside [low, high].
int64_t CheckIntOption(std::string_view env_id, std::string_view option, int64_t value, int64_t low,
                       int64_t high = kNoUpperLimit);
// Returns value, or throws ConfigError unless it is finite and in (low, high].
double CheckFloatOption(std::string_view env_id, std::string_view option, double value,
                        double low_exclusive, double high);

}  // namespace manyworlds::classic

#endif  // MANYWORLDS_CLASSIC_COMMON_H_
