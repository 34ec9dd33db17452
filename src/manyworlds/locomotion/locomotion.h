// Registers the locomotion suite: half-cheetah-vel and half-cheetah-dir
// (family "locomotion"; locomotion/half_cheetah.h documents them).
#ifndef MANYWORLDS_LOCOMOTION_LOCOMOTION_H_
#define MANYWORLDS_LOCOMOTION_LOCOMOTION_H_

#include "manyworlds/core/registry.h"

namespace manyworlds {

void RegisterLocomotionSuite(Registry& registry);

}  // namespace manyworlds

#endif  // MANYWORLDS_LOCOMOTION_LOCOMOTION_H_
