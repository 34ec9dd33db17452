// Registers the DeepMind-Control-style suite (family "dmc"; dmc/dmc_env.h documents it):
//   dmc-finger-spin, dmc-cheetah-run, dmc-walker-walk             dm_control's tasks
//   hipbmdp-finger-spin-size, hipbmdp-cheetah-run-torso-length,
//   hipbmdp-walker-walk-friction, hipbmdp-walker-walk-foot-length MTEnv's HiP-BMDP variants
#ifndef MANYWORLDS_DMC_DMC_H_
#define MANYWORLDS_DMC_DMC_H_

#include "manyworlds/core/registry.h"

namespace manyworlds {

void RegisterDmcSuite(Registry& registry);

}  // namespace manyworlds

#endif  // MANYWORLDS_DMC_DMC_H_
