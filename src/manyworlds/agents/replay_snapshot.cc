#include "manyworlds/agents/replay_snapshot.h"

#include <array>
#include <cstring>
#include <istream>
#include <ostream>
#include <string>

#include "manyworlds/core/error.h"

namespace manyworlds::agents {
namespace {

constexpr std::array<char, 8> kMagic = {'M', 'W', 'R', 'E', 'P', 'L', 'A', 'Y'};
constexpr std::array<char, 8> kFramesMagic = {'M', 'W', 'P', 'I', 'X', 'E', 'L', 'S'};
constexpr uint32_t kVersion = 1;
constexpr uint32_t kEndianMarker = 0x01020304;

// A fast 64-bit checksum over a byte stream (words of 8 bytes, multiply-xor
// mixing); detects truncation and bit flips, not an adversary.
class Checksum {
 public:
  void Update(const void* data, size_t n) {
    const auto* p = static_cast<const unsigned char*>(data);
    while (n > 0 && pending_ > 0) {
      Push(*p++);
      --n;
    }
    while (n >= 8) {
      uint64_t word;
      std::memcpy(&word, p, 8);
      Mix(word);
      p += 8;
      n -= 8;
    }
    while (n > 0) {
      Push(*p++);
      --n;
    }
  }
  uint64_t Digest() const {
    uint64_t h = h_;
    if (pending_ > 0) {
      uint64_t word = 0;
      std::memcpy(&word, buffer_.data(), pending_);
      h = MixInto(h, word ^ (uint64_t{pending_} << 56));
    }
    h ^= count_;
    h ^= h >> 33;
    h *= 0xff51afd7ed558ccdULL;
    h ^= h >> 33;
    return h;
  }

 private:
  static uint64_t MixInto(uint64_t h, uint64_t word) {
    h ^= word;
    h *= 0x9e3779b97f4a7c15ULL;
    h ^= h >> 29;
    return h;
  }
  void Mix(uint64_t word) {
    h_ = MixInto(h_, word);
    count_ += 8;
  }
  void Push(unsigned char c) {
    buffer_[pending_++] = c;
    if (pending_ == 8) {
      uint64_t word;
      std::memcpy(&word, buffer_.data(), 8);
      Mix(word);
      pending_ = 0;
    }
  }

  uint64_t h_ = 0x6a09e667f3bcc909ULL;
  uint64_t count_ = 0;
  std::array<unsigned char, 8> buffer_{};
  size_t pending_ = 0;
};

class Writer {
 public:
  explicit Writer(std::ostream& out) : out_(out) {}
  void Bytes(const void* data, size_t n) {
    if (n == 0) return;
    out_.write(static_cast<const char*>(data), static_cast<std::streamsize>(n));
    if (!out_) throw Error("ReplayBuffer::Save: write failed");
    checksum_.Update(data, n);
  }
  template <typename T>
  void Value(T value) {
    Bytes(&value, sizeof(T));
  }
  template <typename T>
  void Rows(const T* data, int64_t count) {
    if (count > 0) Bytes(data, static_cast<size_t>(count) * sizeof(T));
  }
  void Finish() {
    const uint64_t digest = checksum_.Digest();
    out_.write(reinterpret_cast<const char*>(&digest), sizeof(digest));
    out_.flush();
    if (!out_) throw Error("ReplayBuffer::Save: write failed");
  }

 private:
  std::ostream& out_;
  Checksum checksum_;
};

class Reader {
 public:
  // `what` names the data in errors ("the snapshot", "the frames block").
  explicit Reader(std::istream& in, std::string what = "the snapshot")
      : in_(in), what_(std::move(what)) {}
  void Bytes(void* data, size_t n) {
    in_.read(static_cast<char*>(data), static_cast<std::streamsize>(n));
    if (static_cast<size_t>(in_.gcount()) != n) {
      throw Error("ReplayBuffer::Load: " + what_ + " is truncated");
    }
    checksum_.Update(data, n);
  }
  template <typename T>
  T Value() {
    T value;
    Bytes(&value, sizeof(T));
    return value;
  }
  // Counts bytes already read (a magic checked before the checksum starts).
  void Update(const void* data, size_t n) { checksum_.Update(data, n); }
  template <typename T>
  void Into(std::vector<T>& values, int64_t count) {
    values.resize(static_cast<size_t>(count));
    if (count > 0) Bytes(values.data(), values.size() * sizeof(T));
  }
  void Finish() {
    const uint64_t expected = checksum_.Digest();
    uint64_t stored = 0;
    in_.read(reinterpret_cast<char*>(&stored), sizeof(stored));
    if (in_.gcount() != sizeof(stored)) {
      throw Error("ReplayBuffer::Load: " + what_ + " is truncated (no checksum)");
    }
    if (stored != expected) {
      throw Error("ReplayBuffer::Load: checksum mismatch; " + what_ + " is corrupt");
    }
  }

 private:
  std::istream& in_;
  std::string what_;
  Checksum checksum_;
};

}  // namespace

void WriteReplaySnapshot(std::ostream& out, const ReplayShape& shape,
                         std::span<const ReplayTaskView> tasks) {
  if (static_cast<int64_t>(tasks.size()) != shape.num_tasks) {
    throw Error("ReplayBuffer::Save: " + std::to_string(tasks.size()) + " task views for " +
                std::to_string(shape.num_tasks) + " tasks");
  }
  Writer w(out);
  w.Bytes(kMagic.data(), kMagic.size());
  w.Value(kVersion);
  w.Value(kEndianMarker);
  w.Value(shape.obs_dim);
  w.Value(shape.action_dim);
  w.Value(shape.num_tasks);
  w.Value(shape.capacity_per_task);
  for (const ReplayTaskView& task : tasks) w.Value(task.size);
  for (const ReplayTaskView& task : tasks) w.Value(task.next);
  for (const ReplayTaskView& task : tasks) {
    w.Rows(task.obs, task.size * shape.obs_dim);
    w.Rows(task.action, task.size * shape.action_dim);
    w.Rows(task.reward, task.size);
    w.Rows(task.next_obs, task.size * shape.obs_dim);
    w.Rows(task.done, task.size);
    w.Rows(task.task_index, task.size);
  }
  w.Finish();
}

std::vector<ReplayTaskRows> ReadReplaySnapshot(std::istream& in, const ReplayShape& shape) {
  Reader r(in);
  std::array<char, 8> magic{};
  r.Bytes(magic.data(), magic.size());
  if (magic != kMagic) throw Error("ReplayBuffer::Load: not a replay buffer snapshot");
  const auto version = r.Value<uint32_t>();
  if (version != kVersion) {
    throw Error("ReplayBuffer::Load: snapshot format version " + std::to_string(version) +
                ", this build reads version " + std::to_string(kVersion));
  }
  if (r.Value<uint32_t>() != kEndianMarker) {
    throw Error("ReplayBuffer::Load: the snapshot was written with another byte order");
  }
  const std::array<int64_t, 4> want = {shape.obs_dim, shape.action_dim, shape.num_tasks,
                                       shape.capacity_per_task};
  const std::array<const char*, 4> names = {"obs_dim", "action_dim", "num_tasks",
                                            "capacity_per_task"};
  for (size_t i = 0; i < want.size(); ++i) {
    const auto got = r.Value<int64_t>();
    if (got != want[i]) {
      throw Error(std::string("ReplayBuffer::Load: the snapshot has ") + names[i] + " " +
                  std::to_string(got) + ", this buffer " + std::to_string(want[i]));
    }
  }
  std::vector<ReplayTaskRows> tasks(static_cast<size_t>(shape.num_tasks));
  for (ReplayTaskRows& task : tasks) task.size = r.Value<int64_t>();
  for (ReplayTaskRows& task : tasks) task.next = r.Value<int64_t>();
  const int64_t capacity = shape.capacity_per_task;
  for (size_t t = 0; t < tasks.size(); ++t) {
    const int64_t size = tasks[t].size, next = tasks[t].next;
    const bool ok = size >= 0 && size <= capacity && next >= 0 && next < capacity &&
                    (size == capacity || next == size);
    if (!ok) {
      throw Error("ReplayBuffer::Load: the snapshot is corrupt (task " + std::to_string(t) +
                  " has size " + std::to_string(size) + ", next " + std::to_string(next) + ")");
    }
  }
  std::vector<std::vector<int64_t>> task_index(tasks.size());
  for (size_t t = 0; t < tasks.size(); ++t) {
    ReplayTaskRows& task = tasks[t];
    r.Into(task.obs, task.size * shape.obs_dim);
    r.Into(task.action, task.size * shape.action_dim);
    r.Into(task.reward, task.size);
    r.Into(task.next_obs, task.size * shape.obs_dim);
    r.Into(task.done, task.size);
    r.Into(task_index[t], task.size);
  }
  r.Finish();
  for (size_t t = 0; t < tasks.size(); ++t) {
    for (int64_t index : task_index[t]) {
      if (index != static_cast<int64_t>(t)) {
        throw Error("ReplayBuffer::Load: the snapshot is corrupt (foreign task index in task " +
                    std::to_string(t) + ")");
      }
    }
  }
  return tasks;
}

void WriteReplayFrames(std::ostream& out, int64_t pixel_size,
                       std::span<const ReplayTaskFramesView> tasks) {
  Writer w(out);
  w.Bytes(kFramesMagic.data(), kFramesMagic.size());
  w.Value(pixel_size);
  for (const ReplayTaskFramesView& task : tasks) {
    w.Rows(task.pixels, task.size * pixel_size);
    w.Rows(task.next_pixels, task.size * pixel_size);
  }
  w.Finish();
}

std::vector<ReplayTaskFrames> ReadReplayFrames(std::istream& in, int64_t pixel_size,
                                               std::span<const int64_t> sizes) {
  Reader r(in, "the frames block");
  std::array<char, 8> magic{};
  in.read(magic.data(), static_cast<std::streamsize>(magic.size()));
  if (in.gcount() != static_cast<std::streamsize>(magic.size()) || magic != kFramesMagic) {
    throw Error("ReplayBuffer::Load: no frames block after the transitions (saved by a buffer "
                "without pixels?)");
  }
  r.Update(magic.data(), magic.size());
  const auto saved = r.Value<int64_t>();
  if (saved != pixel_size) {
    throw Error("ReplayBuffer::Load: frames of " + std::to_string(saved) +
                " bytes, this buffer's are " + std::to_string(pixel_size));
  }
  std::vector<ReplayTaskFrames> tasks(sizes.size());
  for (size_t t = 0; t < sizes.size(); ++t) {
    r.Into(tasks[t].pixels, sizes[t] * pixel_size);
    r.Into(tasks[t].next_pixels, sizes[t] * pixel_size);
  }
  r.Finish();
  return tasks;
}

uint64_t ReplaySnapshotChecksum(std::span<const char> bytes) {
  Checksum checksum;
  checksum.Update(bytes.data(), bytes.size());
  return checksum.Digest();
}

}  // namespace manyworlds::agents
