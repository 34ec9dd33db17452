// SIGINT, SIGTERM and SIGHUP during a long command (train, render): the
// first one is only recorded, so the command stops at its next safe point
// and cleans up (train: a final checkpoint; render: the temporary video is
// removed); a second one ends the process at once, as by default.
#ifndef MANYWORLDS_APPS_MANYWORLDS_STOP_SIGNALS_H_
#define MANYWORLDS_APPS_MANYWORLDS_STOP_SIGNALS_H_

#include <csignal>

namespace manyworlds::cli {

class StopSignals {
 public:
  StopSignals();   // installs the handlers (forgetting any earlier signal)
  ~StopSignals();  // restores the previous handlers
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

  // The first signal received while installed, or 0.
  static int received();
  // 128 + the signal: the exit code of a command it stopped.
  static int exit_code() { return 128 + received(); }

 private:
  struct sigaction previous_[3];
};

}  // namespace manyworlds::cli

#endif  // MANYWORLDS_APPS_MANYWORLDS_STOP_SIGNALS_H_
