// TaskState: everything an environment needs to run one task again, on
// another instance or in another process.
//
// A task state is {"env": <family id>, "params": {...}}. The params object is
// owned by the env family and documented in its header. Numbers are stored as
// JSON doubles, which nlohmann::json prints with round-trip precision, so a
// state survives Dump()/Parse() exactly.
#ifndef MANYWORLDS_CORE_TASK_STATE_H_
#define MANYWORLDS_CORE_TASK_STATE_H_

#include <cstdint>
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "manyworlds/core/error.h"

namespace manyworlds {

struct TaskState {
  std::string env;        // family that produced it, e.g. "cartpole"
  nlohmann::json params;  // family-specific object

  nlohmann::json ToJson() const;
  // Throws TaskStateError if the JSON is not {"env": string, "params": object}.
  static TaskState FromJson(const nlohmann::json& json);
  std::string Dump(int indent = -1) const;
  // Throws TaskStateError on malformed text.
  static TaskState Parse(std::string_view text);

  bool operator==(const TaskState& other) const = default;
};

// Validating accessor for a task state's params. Every failure throws
// TaskStateError naming the env, the field and what is allowed.
class TaskStateReader {
 public:
  // Checks that state.env == env_id and that params is an object.
  TaskStateReader(const TaskState& state, std::string_view env_id);

  double Number(std::string_view key, double low, double high) const;
  int64_t Integer(std::string_view key, int64_t low, int64_t high) const;
  // An array of exactly `size` numbers, each in [low, high].
  std::vector<double> Numbers(std::string_view key, size_t size, double low, double high) const;
  std::vector<float> Floats(std::string_view key, size_t size, double low, double high) const;
  // Fails if params holds a key that is not listed.
  void ExpectKeys(std::initializer_list<std::string_view> keys) const;

 private:
  const nlohmann::json& Field(std::string_view key) const;
  [[noreturn]] void Fail(std::string_view key, const std::string& what) const;

  const TaskState& state_;
  std::string env_id_;
};

// Task states that pick one of several tasks by index and embed the picked
// task's own state: {"index": i, "task": <its task state>} (MultiEnv,
// NTasksId).
TaskState MakeIndexedTaskState(std::string_view env_id, int index, const TaskState& task);
struct IndexedTaskState {
  int index = 0;
  TaskState task;
};
// Reads one for env `env_id` whose index must lie in [0, count). Throws
// TaskStateError naming the field that is missing or wrong.
IndexedTaskState ReadIndexedTaskState(const TaskState& state, std::string_view env_id, int count);
// The error to throw when `task_env` (e.g. "env 'cartpole'") rejected the
// embedded task with `error`.
TaskStateError IndexedTaskRejected(std::string_view env_id, std::string_view task_env,
                                   const TaskStateError& error);

}  // namespace manyworlds

#endif  // MANYWORLDS_CORE_TASK_STATE_H_
