// All core wrappers in one include.
#ifndef MANYWORLDS_CORE_WRAPPERS_H_
#define MANYWORLDS_CORE_WRAPPERS_H_

#include "manyworlds/core/wrappers/action_repeat.h"        // IWYU pragma: export
#include "manyworlds/core/wrappers/append_task_one_hot.h"  // IWYU pragma: export
#include "manyworlds/core/wrappers/frame_stack.h"          // IWYU pragma: export
#include "manyworlds/core/wrappers/multi_env.h"            // IWYU pragma: export
#include "manyworlds/core/wrappers/ntasks.h"               // IWYU pragma: export
#include "manyworlds/core/wrappers/ntasks_id.h"            // IWYU pragma: export
#include "manyworlds/core/wrappers/recurrent_meta_obs.h"   // IWYU pragma: export
#include "manyworlds/core/wrappers/sample_random_task.h"   // IWYU pragma: export
#include "manyworlds/core/wrappers/terminate_on_success.h"  // IWYU pragma: export
#include "manyworlds/core/wrappers/time_limit.h"           // IWYU pragma: export

#endif  // MANYWORLDS_CORE_WRAPPERS_H_
