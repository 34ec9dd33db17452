// NTasks: restricts an env to a fixed set of n tasks.
//
// The set is drawn from the inner env's SampleTaskState the first time a
// task is needed (so SeedTask before that point decides it) and then stays
// fixed for the wrapper's lifetime; later SampleTaskState calls return one of
// the cached states, chosen uniformly with the wrapper's task generator.
//
// Task states are the inner env's own, so they stay self-contained and any
// instance of the inner env accepts them; SetTaskState does not require the
// state to belong to the cached set.
//
//   auto env = std::make_unique<NTasks>(MakeToy(), 10);
#ifndef MANYWORLDS_CORE_WRAPPERS_NTASKS_H_
#define MANYWORLDS_CORE_WRAPPERS_NTASKS_H_

#include <cstdint>
#include <memory>
#include <string_view>
#include <vector>

#include "manyworlds/core/wrapper.h"

namespace manyworlds {

class NTasks : public Wrapper {
 public:
  // Throws ConfigError if n < 1.
  NTasks(std::unique_ptr<Env> inner, int n);

  // Seeds the inner env's task generator (which draws the set) with seed and
  // the wrapper's own (which picks from it) with a seed mixed from it, so the
  // two streams are independent.
  void SeedTask(uint64_t seed) override;

  int n() const { return n_; }
  // The fixed task set, drawn from the inner env on the first call.
  const std::vector<TaskState>& tasks();

 protected:
  // For derived wrappers that present the same task set differently.
  NTasks(std::unique_ptr<Env> inner, int n, std::string_view name);

  TaskState DoSampleTaskState(Rng& task_rng) override;
  // Picks a task index with the wrapper's task generator.
  int SampleIndex(Rng& task_rng);

 private:
  int n_;
  std::vector<TaskState> tasks_;
};

}  // namespace manyworlds

#endif  // MANYWORLDS_CORE_WRAPPERS_NTASKS_H_
