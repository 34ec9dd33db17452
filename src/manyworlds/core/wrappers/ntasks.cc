#include "manyworlds/core/wrappers/ntasks.h"

#include <string>

#include "manyworlds/core/error.h"

namespace manyworlds {
namespace {

// Validates n before the base class is built, so the error names the env.
std::unique_ptr<Env> CheckTaskCount(std::unique_ptr<Env> inner, int n, std::string_view name) {
  if (n < 1) {
    throw ConfigError("wrapper " + std::string(name) + " on env '" +
                      (inner ? inner->id() : std::string("<null>")) +
                      "': the number of tasks must be >= 1, got " + std::to_string(n));
  }
  return inner;
}

}  // namespace

NTasks::NTasks(std::unique_ptr<Env> inner, int n)
    : NTasks(std::move(inner), n, "ntasks(" + std::to_string(n) + ")") {}

NTasks::NTasks(std::unique_ptr<Env> inner, int n, std::string_view name)
    : Wrapper(CheckTaskCount(std::move(inner), n, name), name), n_(n) {
  // Unseeded behaves as SeedTask(0) would for this wrapper's own generator
  // (the inner env keeps whatever task seed it has).
  Env::SeedTask(MixSeed(0, 1));
}

void NTasks::SeedTask(uint64_t seed) {
  Wrapper::SeedTask(seed);
  Env::SeedTask(MixSeed(seed, 1));
}

const std::vector<TaskState>& NTasks::tasks() {
  if (tasks_.empty()) {
    std::vector<TaskState> drawn;
    drawn.reserve(n_);
    for (int i = 0; i < n_; ++i) drawn.push_back(inner().SampleTaskState());
    tasks_ = std::move(drawn);
  }
  return tasks_;
}

int NTasks::SampleIndex(Rng& task_rng) {
  tasks();  // the set is drawn before the first index, as MTEnv does
  return static_cast<int>(task_rng.UniformInt(static_cast<uint64_t>(n_)));
}

TaskState NTasks::DoSampleTaskState(Rng& task_rng) { return tasks()[SampleIndex(task_rng)]; }

}  // namespace manyworlds
