// Registers the box world suite (family "boxworld"): box-world-simple and
// box-world-complex, whose options are the generator's ranges
// (docs/boxworld.md).
#ifndef MANYWORLDS_BOXWORLD_BOXWORLD_H_
#define MANYWORLDS_BOXWORLD_BOXWORLD_H_

#include <memory>

#include "manyworlds/boxworld/box_world_env.h"
#include "manyworlds/core/registry.h"

namespace manyworlds {

void RegisterBoxWorldSuite(Registry& registry);

}  // namespace manyworlds

#endif  // MANYWORLDS_BOXWORLD_BOXWORLD_H_
