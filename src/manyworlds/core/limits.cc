#include "manyworlds/core/limits.h"

#include "manyworlds/core/error.h"

namespace manyworlds {

void ThrowThreadsNotStarted(const std::exception& cause, int64_t started, int64_t wanted,
                            const std::string& setting) {
  throw Error("cannot start thread " + std::to_string(started + 1) + " of " +
              std::to_string(wanted) + " (" + cause.what() + "); lower " + setting);
}

}  // namespace manyworlds
