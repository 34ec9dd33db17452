// Multi-task replay buffer for off-policy learners (SAC and its MT variants).
//
//   ReplayBuffer replay(/*capacity=*/100000, obs_dim, action_dim, num_tasks);
//   replay.Add(task, obs, action, reward, next_obs, terminated);
//   const Batch& batch = replay.Sample(256, ReplaySampling::kBalanced, generator);
//   learner.Update(batch);
//
// Storage: one contiguous CPU tensor per field, `capacity` rows split evenly
// into one partition per task (capacity / num_tasks rows each, the remainder
// unused). Each partition is a ring buffer: once full, the oldest transition
// of that task is overwritten, so a task that steps faster cannot evict the
// others. Memory is the raw transition bytes (float32 obs, action, reward,
// next_obs, done; int64 task index) times the rows, plus the batch buffers:
// bytes() reports it.
//
// Sampling draws from an explicit torch generator, so a run is reproducible
// and its sampling stream can be checkpointed with the generator's state:
//  - kUniform: every stored transition equally likely (tasks in proportion
//    to how much of them is stored);
//  - kBalanced: batch_size / num_tasks transitions from each task (MTRL's
//    per-task balanced batch); batch_size must be a multiple of num_tasks and
//    every task must hold a transition.
// Sample writes into tensors owned by the buffer and reused by the next
// Sample of the same size: consume (or clone) the batch before sampling again.
//
// Pixel observations (pixel_size > 0, for learners that read obs=pixels
// frames): every row also holds the frames of obs and next_obs as uint8
// (2 * pixel_size bytes; MTRL's and SAC-AE's buffers store both frames the
// same way), and batches carry them (Batch::pixels, next_pixels). Snapshots
// append them after the state rows, in a block with its own checksum.
//
// done is `terminated` only; a time-limit truncation is stored as not done so
// the learner bootstraps from next_obs.
//
// Not thread-safe.
#ifndef MANYWORLDS_AGENTS_REPLAY_BUFFER_H_
#define MANYWORLDS_AGENTS_REPLAY_BUFFER_H_

#include <cstdint>
#include <filesystem>
#include <iosfwd>
#include <span>
#include <string_view>
#include <vector>

#include <torch/torch.h>

#include "manyworlds/agents/batch.h"
#include "manyworlds/agents/replay_snapshot.h"

namespace manyworlds::agents {

enum class ReplaySampling { kUniform, kBalanced };

// "uniform" | "balanced"; throws ConfigError naming the allowed values.
ReplaySampling ParseReplaySampling(std::string_view name);
const char* ReplaySamplingName(ReplaySampling sampling);

class ReplayBuffer {
 public:
  // Throws ConfigError if a dim is < 1, capacity < num_tasks, pixel_size < 0,
  // or the storage would not fit in memory.
  ReplayBuffer(int64_t capacity, int64_t obs_dim, int64_t action_dim, int64_t num_tasks = 1,
               int64_t pixel_size = 0);
  ReplayBuffer(const ReplayBuffer&) = delete;
  ReplayBuffer& operator=(const ReplayBuffer&) = delete;
  ReplayBuffer(ReplayBuffer&&) = default;
  ReplayBuffer& operator=(ReplayBuffer&&) = default;

  // Stores one transition in the task's partition. obs and next_obs hold
  // obs_dim values, action action_dim. Throws Error on a size mismatch or a
  // task outside [0, num_tasks).
  void Add(int64_t task, std::span<const float> obs, std::span<const float> action, float reward,
           std::span<const float> next_obs, bool done);
  // The same with the frames of obs and next_obs (pixel_size bytes each);
  // Error on a size mismatch, or frames given to (or missing from) a buffer
  // with(out) pixels.
  void Add(int64_t task, std::span<const float> obs, std::span<const float> action, float reward,
           std::span<const float> next_obs, bool done, std::span<const uint8_t> pixels,
           std::span<const uint8_t> next_pixels);

  // A batch of batch_size transitions (see the sampling modes above). Throws
  // Error if the buffer (or, balanced, a task) is empty or batch_size < 1.
  const Batch& Sample(int64_t batch_size, ReplaySampling sampling, at::Generator& generator);

  // per_task transitions from each listed task (repeats allowed), drawn
  // uniformly with replacement, rows grouped by task in list order (PEARL's
  // per-task batches). Throws Error on an empty list, per_task < 1, or a
  // task that is out of range or holds nothing.
  const Batch& SampleTasks(std::span<const int64_t> tasks, int64_t per_task,
                           at::Generator& generator);

  int64_t obs_dim() const { return obs_dim_; }
  int64_t pixel_size() const { return pixel_size_; }
  int64_t action_dim() const { return action_dim_; }
  int64_t num_tasks() const { return num_tasks_; }
  int64_t capacity_per_task() const { return capacity_per_task_; }
  // The dims and partition size, as a snapshot records them.
  ReplayShape shape() const;
  // Rows actually allocated: capacity_per_task * num_tasks.
  int64_t capacity() const { return capacity_per_task_ * num_tasks_; }
  int64_t size() const;                 // transitions stored, all tasks
  int64_t size(int64_t task) const;     // transitions stored for one task
  // Bytes of one stored transition (all fields).
  int64_t transition_bytes() const;
  // Bytes held: storage plus the current batch buffers.
  int64_t bytes() const;

  // Forgets every transition (keeps the allocation).
  void Clear();
  // Forgets one task's transitions (PEARL's encoder buffer is refilled from
  // recent data only). Throws Error for a task out of range.
  void ClearTask(int64_t task);

  // Binary snapshot of the stored transitions and ring positions, with a
  // header (format, dims, partition size) and a checksum (the format:
  // replay_snapshot.h). Throws Error if the stream fails.
  void Save(std::ostream& out) const;
  // Restores a Save. Throws Error, leaving this buffer unchanged, if the data
  // is not a replay snapshot, is truncated or corrupt (checksum), or was
  // saved with other dims, task count or per-task capacity.
  void Load(std::istream& in);
  // File versions; errors name the path.
  void SaveFile(const std::filesystem::path& path) const;
  void LoadFile(const std::filesystem::path& path);

 private:
  struct Storage {
    torch::Tensor obs;         // (rows, obs_dim) float32
    torch::Tensor action;      // (rows, action_dim) float32
    torch::Tensor reward;      // (rows) float32
    torch::Tensor next_obs;    // (rows, obs_dim) float32
    torch::Tensor done;        // (rows) float32, 1 = terminated
    torch::Tensor task_index;  // (rows) int64
    torch::Tensor pixels;      // (rows, pixel_size) uint8, undefined without pixels
    torch::Tensor next_pixels;
  };
  static Storage Allocate(int64_t rows, int64_t obs_dim, int64_t action_dim, int64_t pixel_size);
  // Error on a task out of range or a row of the wrong size.
  void CheckRow(int64_t task, std::span<const float> obs, std::span<const float> action,
                std::span<const float> next_obs) const;
  void AddRow(int64_t task, std::span<const float> obs, std::span<const float> action,
              float reward, std::span<const float> next_obs, bool done);
  void SavePixels(std::ostream& out) const;
  void ResizeBatch(int64_t batch_size);
  // Copies the rows in rows_ into batch_.
  const Batch& Gather();
  // Row of the `i`th stored transition of a task (oldest-first order is not
  // needed: any bijection onto the stored rows samples uniformly).
  int64_t Row(int64_t task, int64_t i) const { return task * capacity_per_task_ + i; }

  int64_t obs_dim_;
  int64_t action_dim_;
  int64_t num_tasks_;
  int64_t pixel_size_;
  int64_t capacity_per_task_;
  Storage storage_;
  std::vector<int64_t> size_;  // (num_tasks) stored per partition
  std::vector<int64_t> next_;  // (num_tasks) next row to write, in [0, capacity_per_task)
  Batch batch_;                // reused output of Sample
  torch::Tensor rows_;         // (B) int64 rows of the current batch
};

}  // namespace manyworlds::agents

#endif  // MANYWORLDS_AGENTS_REPLAY_BUFFER_H_
