// Any bytes as a replay buffer snapshot (replay.bin): ReadReplaySnapshot,
// the reader behind ReplayBuffer::Load, returns the rows or throws Error; what
// it returns writes back (WriteReplaySnapshot, behind Save) to the very bytes
// it read. The format code has no libtorch, so this target needs none
// (ReplayBuffer::Load only copies the returned rows into its tensors).
//
// Input: one flag byte, then the snapshot. Flag bit 0: the harness appends
// the right checksum (ReplaySnapshotChecksum), so that the fuzzer gets past
// it to the rows and their checks. Bits 1-2 pick the shape the snapshot must
// match: 0: obs_dim 3, action_dim 2, 2 tasks of 4 rows; 1: obs_dim 1,
// action_dim 1, 3 tasks of 2 rows; 2, 3: the shape the header states, when
// every number of it is in [1, 64] (else the first shape).
//
// MANYWORLDS_FUZZ_WRITE_SEEDS=DIR writes the seed inputs (the corpus in
// tests/fuzz/corpus/replay/) into DIR and exits.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "manyworlds/agents/replay_snapshot.h"
#include "manyworlds/core/error.h"

namespace {

using manyworlds::agents::ReplayShape;
using manyworlds::agents::ReplayTaskRows;
using manyworlds::agents::ReplayTaskView;

constexpr ReplayShape kShapes[2] = {{3, 2, 2, 4}, {1, 1, 3, 2}};

ReplayShape ShapeOf(uint8_t flags, const std::string& snapshot) {
  const int pick = (flags >> 1) & 3;
  if (pick < 2) return kShapes[pick];
  // header: 8 magic bytes, two u32, then the four i64 of the shape
  int64_t v[4];
  if (snapshot.size() < 16 + sizeof(v)) return kShapes[0];
  std::memcpy(v, snapshot.data() + 16, sizeof(v));
  for (int64_t x : v) {
    if (x < 1 || x > 64) return kShapes[0];
  }
  return {v[0], v[1], v[2], v[3]};
}

// Writes `tasks` as Save would.
std::string Written(const ReplayShape& shape, const std::vector<ReplayTaskRows>& tasks) {
  std::vector<std::vector<int64_t>> task_index(tasks.size());
  std::vector<ReplayTaskView> views(tasks.size());
  for (size_t t = 0; t < tasks.size(); ++t) {
    const ReplayTaskRows& task = tasks[t];
    task_index[t].assign(static_cast<size_t>(task.size), static_cast<int64_t>(t));
    views[t] = {task.size,          task.next,           task.obs.data(),
                task.action.data(), task.reward.data(),  task.next_obs.data(),
                task.done.data(),   task_index[t].data()};
  }
  std::ostringstream out;
  manyworlds::agents::WriteReplaySnapshot(out, shape, views);
  return out.str();
}

// A partition of `size` rows with distinct values, ring position `next`.
ReplayTaskRows Rows(const ReplayShape& shape, int64_t task, int64_t size, int64_t next) {
  ReplayTaskRows rows;
  rows.size = size;
  rows.next = next;
  for (int64_t i = 0; i < size; ++i) {
    const float base = static_cast<float>(100 * task + i);
    for (int64_t k = 0; k < shape.obs_dim; ++k) rows.obs.push_back(base + 0.25f * k);
    for (int64_t k = 0; k < shape.action_dim; ++k) rows.action.push_back(-0.5f + 0.1f * k);
    rows.reward.push_back(0.5f * base);
    for (int64_t k = 0; k < shape.obs_dim; ++k) rows.next_obs.push_back(base + 1.0f + 0.25f * k);
    rows.done.push_back(i % 3 == 0 ? 1.0f : 0.0f);
  }
  return rows;
}

void WriteSeeds(const std::string& dir) {
  for (int s = 0; s < 2; ++s) {
    const ReplayShape& shape = kShapes[s];
    const int64_t cap = shape.capacity_per_task;
    // empty; partly filled; full (next wrapped to 0); full and wrapped past 0
    const std::vector<std::pair<const char*, std::vector<std::pair<int64_t, int64_t>>>> fills = {
        {"empty", std::vector<std::pair<int64_t, int64_t>>(shape.num_tasks, {0, 0})},
        {"partial", std::vector<std::pair<int64_t, int64_t>>(shape.num_tasks, {1, 1})},
        {"full", std::vector<std::pair<int64_t, int64_t>>(shape.num_tasks, {cap, 0})},
        {"wrapped", std::vector<std::pair<int64_t, int64_t>>(shape.num_tasks, {cap, 1})},
    };
    for (const auto& [name, fill] : fills) {
      std::vector<ReplayTaskRows> tasks;
      for (int64_t t = 0; t < shape.num_tasks; ++t) {
        tasks.push_back(Rows(shape, t, fill[t].first, fill[t].second));
      }
      const std::string path = dir + "/shape" + std::to_string(s) + "_" + name;
      std::ofstream out(path, std::ios::binary);
      out << static_cast<char>(s << 1) << Written(shape, tasks);  // checksum included
      if (!out) {
        std::fprintf(stderr, "cannot write %s\n", path.c_str());
        std::exit(1);
      }
    }
  }
  std::exit(0);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (const char* dir = std::getenv("MANYWORLDS_FUZZ_WRITE_SEEDS")) WriteSeeds(dir);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  std::string snapshot(reinterpret_cast<const char*>(data + 1), size - 1);
  if (data[0] & 1) {
    const uint64_t sum = manyworlds::agents::ReplaySnapshotChecksum(snapshot);
    snapshot.append(reinterpret_cast<const char*>(&sum), sizeof(sum));
  }
  const ReplayShape shape = ShapeOf(data[0], snapshot);
  std::istringstream in(snapshot);
  std::vector<ReplayTaskRows> tasks;
  try {
    tasks = manyworlds::agents::ReadReplaySnapshot(in, shape);
  } catch (const manyworlds::Error&) {
    return 0;
  }
  // one partition per task, each as large as it says and within the shape
  if (static_cast<int64_t>(tasks.size()) != shape.num_tasks) std::abort();
  for (const ReplayTaskRows& task : tasks) {
    if (task.size < 0 || task.size > shape.capacity_per_task || task.next < 0 ||
        task.next >= shape.capacity_per_task ||
        task.obs.size() != static_cast<size_t>(task.size * shape.obs_dim) ||
        task.action.size() != static_cast<size_t>(task.size * shape.action_dim) ||
        task.reward.size() != static_cast<size_t>(task.size) ||
        task.next_obs.size() != static_cast<size_t>(task.size * shape.obs_dim) ||
        task.done.size() != static_cast<size_t>(task.size)) {
      std::abort();
    }
  }
  // and writes back to the bytes it was read from (nothing after them is read)
  in.clear();
  const std::streamoff read = in.tellg();
  if (read < 0 || Written(shape, tasks) != snapshot.substr(0, static_cast<size_t>(read))) {
    std::abort();
  }
  return 0;
}
