// The binary format of a replay buffer snapshot (replay.bin in off-policy
// checkpoints), written and read without libtorch: ReplayBuffer::Save and
// Load move rows between it and their tensors, and the fuzz build reads it
// alone (fuzz/replay_fuzz.cc).
//
// Layout (integers little-endian as stored by this machine; the endianness
// marker rejects a foreign byte order):
//   "MWREPLAY" | u32 version | u32 0x01020304 | i64 obs_dim, action_dim,
//   num_tasks, capacity_per_task | i64 size[num_tasks] | i64 next[num_tasks]
//   | per task: its stored rows of obs, action, reward, next_obs, done
//   (float32) and task_index (int64) | u64 checksum of every byte before it
#ifndef MANYWORLDS_AGENTS_REPLAY_SNAPSHOT_H_
#define MANYWORLDS_AGENTS_REPLAY_SNAPSHOT_H_

#include <cstdint>
#include <iosfwd>
#include <span>
#include <vector>

namespace manyworlds::agents {

// The dims and partition size a snapshot is written for and must match.
struct ReplayShape {
  int64_t obs_dim = 0;
  int64_t action_dim = 0;
  int64_t num_tasks = 0;
  int64_t capacity_per_task = 0;
};

// One task's partition as Save writes it: its first `size` rows, each field
// row-major, and the ring position `next`.
struct ReplayTaskView {
  int64_t size = 0;
  int64_t next = 0;
  const float* obs = nullptr;           // size x obs_dim
  const float* action = nullptr;        // size x action_dim
  const float* reward = nullptr;        // size
  const float* next_obs = nullptr;      // size x obs_dim
  const float* done = nullptr;          // size
  const int64_t* task_index = nullptr;  // size, every one the task's index
};

// One task's partition as Load reads it (task_index is checked, not kept).
struct ReplayTaskRows {
  int64_t size = 0;
  int64_t next = 0;
  std::vector<float> obs, action, reward, next_obs, done;
};

// Writes a snapshot of `tasks` (one view per task). Throws Error if the
// stream fails.
void WriteReplaySnapshot(std::ostream& out, const ReplayShape& shape,
                         std::span<const ReplayTaskView> tasks);

// Reads a snapshot written for `shape`: one entry per task. Throws Error if
// the data is not a replay snapshot, is truncated or corrupt (checksum,
// ring positions, a foreign task index), or has other dims, task count or
// per-task capacity. Reads nothing after the checksum.
std::vector<ReplayTaskRows> ReadReplaySnapshot(std::istream& in, const ReplayShape& shape);

// The frames of a buffer with pixel observations, a block of its own after
// the snapshot (state-only snapshots keep their format):
//   "MWPIXELS" | i64 pixel_size | per task: its stored rows of pixels, then of
//   next_pixels (uint8) | u64 checksum of every byte of the block before it
struct ReplayTaskFramesView {
  int64_t size = 0;
  const uint8_t* pixels = nullptr;       // size x pixel_size
  const uint8_t* next_pixels = nullptr;  // size x pixel_size
};
struct ReplayTaskFrames {
  std::vector<uint8_t> pixels, next_pixels;
};
// Streams the block (no copy of the frames). Throws Error if the stream fails.
void WriteReplayFrames(std::ostream& out, int64_t pixel_size,
                       std::span<const ReplayTaskFramesView> tasks);
// Reads the block of tasks holding `sizes` rows. Throws Error if it is
// missing, truncated, corrupt (checksum) or of another frame size.
std::vector<ReplayTaskFrames> ReadReplayFrames(std::istream& in, int64_t pixel_size,
                                               std::span<const int64_t> sizes);

// The checksum a snapshot ends with, of all the bytes before it. It finds
// damage, not forgery: tests and the fuzzer seal hand-made snapshots with it.
uint64_t ReplaySnapshotChecksum(std::span<const char> bytes);

}  // namespace manyworlds::agents

#endif  // MANYWORLDS_AGENTS_REPLAY_SNAPSHOT_H_
