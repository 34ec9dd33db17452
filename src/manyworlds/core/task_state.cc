#include "manyworlds/core/task_state.h"

#include <cmath>

#include "manyworlds/core/error.h"

namespace manyworlds {

nlohmann::json TaskState::ToJson() const { return {{"env", env}, {"params", params}}; }

TaskState TaskState::FromJson(const nlohmann::json& json) {
  if (!json.is_object() || !json.contains("env") || !json.contains("params") ||
      !json["env"].is_string() || !json["params"].is_object() || json.size() != 2) {
    throw TaskStateError(
        "malformed task state: expected an object {\"env\": <string>, \"params\": <object>}, got " +
        json.dump());
  }
  return TaskState{json["env"].get<std::string>(), json["params"]};
}

std::string TaskState::Dump(int indent) const { return ToJson().dump(indent); }

TaskState TaskState::Parse(std::string_view text) {
  nlohmann::json json = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (json.is_discarded()) {
    throw TaskStateError("malformed task state: not valid JSON: " +
                         std::string(text.substr(0, 200)));
  }
  return FromJson(json);
}

TaskStateReader::TaskStateReader(const TaskState& state, std::string_view env_id)
    : state_(state), env_id_(env_id) {
  if (state.env != env_id) {
    throw TaskStateError("task state for env '" + state.env + "' cannot be used by env '" +
                         env_id_ + "'");
  }
  if (!state.params.is_object()) {
    throw TaskStateError("task state for env '" + env_id_ + "': params must be a JSON object");
  }
}

void TaskStateReader::Fail(std::string_view key, const std::string& what) const {
  throw TaskStateError("task state for env '" + env_id_ + "': field '" + std::string(key) + "' " +
                       what);
}

const nlohmann::json& TaskStateReader::Field(std::string_view key) const {
  auto it = state_.params.find(key);
  if (it == state_.params.end()) Fail(key, "is missing");
  return *it;
}

double TaskStateReader::Number(std::string_view key, double low, double high) const {
  const auto& field = Field(key);
  if (!field.is_number()) Fail(key, "must be a number, got " + field.dump());
  const double v = field.get<double>();
  if (!std::isfinite(v) || v < low || v > high) {
    Fail(key, "must lie in [" + std::to_string(low) + ", " + std::to_string(high) + "], got " +
                  field.dump());
  }
  return v;
}

int64_t TaskStateReader::Integer(std::string_view key, int64_t low, int64_t high) const {
  const auto& field = Field(key);
  if (!field.is_number_integer()) Fail(key, "must be an integer, got " + field.dump());
  const int64_t v = field.get<int64_t>();
  if (v < low || v > high) {
    Fail(key, "must lie in [" + std::to_string(low) + ", " + std::to_string(high) + "], got " +
                  std::to_string(v));
  }
  return v;
}

std::vector<double> TaskStateReader::Numbers(std::string_view key, size_t size, double low,
                                             double high) const {
  const auto& field = Field(key);
  if (!field.is_array() || field.size() != size) {
    Fail(key, "must be an array of " + std::to_string(size) + " numbers, got " +
                  field.dump().substr(0, 200));
  }
  std::vector<double> values;
  values.reserve(size);
  for (size_t i = 0; i < size; ++i) {
    const auto& x = field[i];
    if (!x.is_number() || !std::isfinite(x.get<double>()) || x.get<double>() < low ||
        x.get<double>() > high) {
      Fail(key, "element " + std::to_string(i) + " must be a number in [" + std::to_string(low) +
                    ", " + std::to_string(high) + "], got " + x.dump());
    }
    values.push_back(x.get<double>());
  }
  return values;
}

std::vector<float> TaskStateReader::Floats(std::string_view key, size_t size, double low,
                                           double high) const {
  const auto values = Numbers(key, size, low, high);
  return std::vector<float>(values.begin(), values.end());
}

void TaskStateReader::ExpectKeys(std::initializer_list<std::string_view> keys) const {
  for (const auto& [key, value] : state_.params.items()) {
    bool known = false;
    for (auto k : keys) known = known || (k == key);
    if (!known) {
      std::string allowed;
      for (auto k : keys) allowed += (allowed.empty() ? "" : ", ") + std::string(k);
      Fail(key, "is not a field of this env's task state (allowed: " + allowed + ")");
    }
  }
}

namespace {

std::string TaskFieldPrefix(std::string_view env_id) {
  return "task state for env '" + std::string(env_id) + "': field 'task' ";
}

}  // namespace

TaskState MakeIndexedTaskState(std::string_view env_id, int index, const TaskState& task) {
  return TaskState{std::string(env_id), {{"index", index}, {"task", task.ToJson()}}};
}

IndexedTaskState ReadIndexedTaskState(const TaskState& state, std::string_view env_id,
                                      int count) {
  TaskStateReader reader(state, env_id);
  reader.ExpectKeys({"index", "task"});
  IndexedTaskState indexed;
  indexed.index = static_cast<int>(reader.Integer("index", 0, count - 1));
  auto it = state.params.find("task");
  if (it == state.params.end()) throw TaskStateError(TaskFieldPrefix(env_id) + "is missing");
  try {
    indexed.task = TaskState::FromJson(*it);
  } catch (const TaskStateError& e) {
    throw TaskStateError(TaskFieldPrefix(env_id) + "is not a task state: " + e.what());
  }
  return indexed;
}

TaskStateError IndexedTaskRejected(std::string_view env_id, std::string_view task_env,
                                   const TaskStateError& error) {
  return TaskStateError(TaskFieldPrefix(env_id) + "was rejected by " + std::string(task_env) +
                        ": " + error.what());
}

}  // namespace manyworlds
