#include "manyworlds/classic/common.h"

#include <cmath>
#include <sstream>
#include <string>

#include "manyworlds/core/error.h"

namespace manyworlds::classic {

int64_t CheckIntOption(std::string_view env_id, std::string_view option, int64_t value, int64_t low,
                       int64_t high) {
  if (value < low || value > high) {
    std::string allowed = high == kNoUpperLimit
                              ? ">= " + std::to_string(low)
                              : "in [" + std::to_string(low) + ", " + std::to_string(high) + "]";
    throw ConfigError("env '" + std::string(env_id) + "': option '" + std::string(option) +
                      "' must be an integer " + allowed + ", got " + std::to_string(value));
  }
  return value;
}

double CheckFloatOption(std::string_view env_id, std::string_view option, double value,
                        double low_exclusive, double high) {
  if (!std::isfinite(value) || value <= low_exclusive || value > high) {
    std::ostringstream message;
    message << "env '" << env_id << "': option '" << option << "' must be a number in ("
            << low_exclusive << ", " << high << "], got " << value;
    throw ConfigError(message.str());
  }
  return value;
}

}  // namespace manyworlds::classic
