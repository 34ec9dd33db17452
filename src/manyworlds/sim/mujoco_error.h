// MuJoCo errors and warnings as C++ exceptions.
//
// MuJoCo 2.2.2 reports fatal errors through mju_error, which by default
// prints, writes MUJOCO_LOG.TXT and calls exit(). InstallMujocoHandlers()
// replaces the process-wide hooks:
//  - mju_user_error throws MujocoError. This is the mechanism MuJoCo's own
//    model compiler uses (it installs a throwing handler around Compile), so
//    the engine's C frames are built to be unwound; the handler never
//    returns, so execution never continues past an mju_error.
//  - mju_user_warning records the message (thread-local, see
//    LastMujocoWarning) instead of printing or writing a log file.
// Every sim entry point (loading, MakeData) installs them; it is idempotent
// and thread-safe. After a MujocoError thrown from inside mj_step or
// mj_forward the mjData may be half-updated (e.g. its stack not released):
// reset it with mj_resetData before using it again.
#ifndef MANYWORLDS_SIM_MUJOCO_ERROR_H_
#define MANYWORLDS_SIM_MUJOCO_ERROR_H_

#include <string>

#include "manyworlds/core/error.h"

namespace manyworlds::sim {

// A MuJoCo failure: XML parse/compile error, or an mju_error from the engine.
// The message contains MuJoCo's own text.
class MujocoError : public Error {
 public:
  using Error::Error;
};

// The simulation raised warnings (instability, full contact buffer, ...)
// while the caller asked for them to be fatal.
class SimulationWarningError : public Error {
 public:
  using Error::Error;
};

// Installs the throwing error handler and the recording warning handler
// (once per process; later calls do nothing).
void InstallMujocoHandlers();

// The last message passed to mju_warning on this thread ("" if none), and
// the number of such messages since the process started.
const std::string& LastMujocoWarning();
long MujocoWarningCount();

}  // namespace manyworlds::sim

#endif  // MANYWORLDS_SIM_MUJOCO_ERROR_H_
