#include "manyworlds/agents/replay_buffer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <istream>
#include <ostream>
#include <string>

#include "manyworlds/core/error.h"
#include "manyworlds/core/memory.h"

namespace manyworlds::agents {
namespace {

// snapshot layout (all integers little-endian as stored by this machine;
// the endianness marker rejects a foreign byte order):
//   "MWREPLAY" | u32 version | u32 0x01020304 | i64 obs_dim, action_dim,
//   num_tasks, capacity_per_task | i64 size[num_tasks] | i64 next[num_tasks]
//   | per task: its stored rows of obs, action, reward, next_obs, done,
//   task_index | u64 checksum of every byte before it
constexpr std::array<char, 8> kMagic = {'M', 'W', 'R', 'E', 'P', 'L', 'A', 'Y'};
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
    out_.write(static_cast<const char*>(data), static_cast<std::streamsize>(n));
    if (!out_) throw Error("ReplayBuffer::Save: write failed");
    checksum_.Update(data, n);
  }
  template <typename T>
  void Value(T value) {
    Bytes(&value, sizeof(T));
  }
  void Rows(const torch::Tensor& t, int64_t first, int64_t count) {
    if (count == 0) return;
    const torch::Tensor rows = t.narrow(0, first, count);
    Bytes(rows.data_ptr(), rows.nbytes());
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
  explicit Reader(std::istream& in) : in_(in) {}
  void Bytes(void* data, size_t n) {
    in_.read(static_cast<char*>(data), static_cast<std::streamsize>(n));
    if (static_cast<size_t>(in_.gcount()) != n) {
      throw Error("ReplayBuffer::Load: the snapshot is truncated");
    }
    checksum_.Update(data, n);
  }
  template <typename T>
  T Value() {
    T value;
    Bytes(&value, sizeof(T));
    return value;
  }
  void Into(torch::Tensor& t) {
    if (t.numel() > 0) Bytes(t.data_ptr(), t.nbytes());
  }
  void Finish() {
    const uint64_t expected = checksum_.Digest();
    uint64_t stored = 0;
    in_.read(reinterpret_cast<char*>(&stored), sizeof(stored));
    if (in_.gcount() != sizeof(stored)) {
      throw Error("ReplayBuffer::Load: the snapshot is truncated (no checksum)");
    }
    if (stored != expected) {
      throw Error("ReplayBuffer::Load: checksum mismatch; the snapshot is corrupt");
    }
  }

 private:
  std::istream& in_;
  Checksum checksum_;
};

void CheckSize(std::string_view what, size_t got, int64_t want) {
  if (static_cast<int64_t>(got) != want) {
    throw Error("ReplayBuffer::Add: " + std::string(what) + " has " + std::to_string(got) +
                " values, expected " + std::to_string(want));
  }
}

}  // namespace

ReplaySampling ParseReplaySampling(std::string_view name) {
  if (name == "uniform") return ReplaySampling::kUniform;
  if (name == "balanced") return ReplaySampling::kBalanced;
  throw ConfigError("replay sampling must be 'uniform' or 'balanced', got '" + std::string(name) +
                    "'");
}

const char* ReplaySamplingName(ReplaySampling sampling) {
  return sampling == ReplaySampling::kBalanced ? "balanced" : "uniform";
}

ReplayBuffer::Storage ReplayBuffer::Allocate(int64_t rows, int64_t obs_dim, int64_t action_dim) {
  Storage s;
  const auto f32 = torch::TensorOptions().dtype(torch::kFloat32);
  s.obs = torch::zeros({rows, obs_dim}, f32);
  s.action = torch::zeros({rows, action_dim}, f32);
  s.reward = torch::zeros({rows}, f32);
  s.next_obs = torch::zeros({rows, obs_dim}, f32);
  s.done = torch::zeros({rows}, f32);
  s.task_index = torch::zeros({rows}, torch::kInt64);
  return s;
}

ReplayBuffer::ReplayBuffer(int64_t capacity, int64_t obs_dim, int64_t action_dim,
                           int64_t num_tasks)
    : obs_dim_(obs_dim), action_dim_(action_dim), num_tasks_(num_tasks) {
  if (obs_dim < 1 || action_dim < 1 || num_tasks < 1) {
    throw ConfigError("ReplayBuffer: obs_dim, action_dim and num_tasks must be >= 1, got " +
                      std::to_string(obs_dim) + ", " + std::to_string(action_dim) + ", " +
                      std::to_string(num_tasks));
  }
  if (capacity < num_tasks) {
    throw ConfigError("ReplayBuffer: capacity must be >= num_tasks (" +
                      std::to_string(num_tasks) + "), got " + std::to_string(capacity));
  }
  capacity_per_task_ = capacity / num_tasks;
  // obs, next_obs, action, reward, done as float32 and the task index as int64
  CheckMemoryEstimate(static_cast<double>(capacity_per_task_ * num_tasks) *
                          (4.0 * (2.0 * obs_dim + action_dim + 2.0) + 8.0),
                      "a replay buffer of " + std::to_string(capacity) + " transitions (obs " +
                          std::to_string(obs_dim) + ")",
                      "replay.capacity");
  storage_ = Allocate(capacity_per_task_ * num_tasks, obs_dim, action_dim);
  // task index of every row is fixed by its partition
  auto index = storage_.task_index.accessor<int64_t, 1>();
  for (int64_t t = 0; t < num_tasks; ++t) {
    for (int64_t i = 0; i < capacity_per_task_; ++i) index[Row(t, i)] = t;
  }
  size_.assign(num_tasks, 0);
  next_.assign(num_tasks, 0);
}

void ReplayBuffer::Add(int64_t task, std::span<const float> obs, std::span<const float> action,
                       float reward, std::span<const float> next_obs, bool done) {
  if (task < 0 || task >= num_tasks_) {
    throw Error("ReplayBuffer::Add: task " + std::to_string(task) + " is outside [0, " +
                std::to_string(num_tasks_) + ")");
  }
  CheckSize("obs", obs.size(), obs_dim_);
  CheckSize("action", action.size(), action_dim_);
  CheckSize("next_obs", next_obs.size(), obs_dim_);
  const int64_t row = Row(task, next_[task]);
  std::memcpy(storage_.obs.data_ptr<float>() + row * obs_dim_, obs.data(),
              obs.size_bytes());
  std::memcpy(storage_.action.data_ptr<float>() + row * action_dim_, action.data(),
              action.size_bytes());
  storage_.reward.data_ptr<float>()[row] = reward;
  std::memcpy(storage_.next_obs.data_ptr<float>() + row * obs_dim_, next_obs.data(),
              next_obs.size_bytes());
  storage_.done.data_ptr<float>()[row] = done ? 1.0f : 0.0f;
  next_[task] = (next_[task] + 1) % capacity_per_task_;
  size_[task] = std::min(size_[task] + 1, capacity_per_task_);
}

int64_t ReplayBuffer::size() const {
  int64_t total = 0;
  for (int64_t s : size_) total += s;
  return total;
}

int64_t ReplayBuffer::size(int64_t task) const {
  if (task < 0 || task >= num_tasks_) {
    throw Error("ReplayBuffer::size: task " + std::to_string(task) + " is outside [0, " +
                std::to_string(num_tasks_) + ")");
  }
  return size_[task];
}

int64_t ReplayBuffer::transition_bytes() const {
  return static_cast<int64_t>(sizeof(float)) * (2 * obs_dim_ + action_dim_ + 2) +
         static_cast<int64_t>(sizeof(int64_t));
}

int64_t ReplayBuffer::bytes() const {
  auto nbytes = [](const torch::Tensor& t) {
    return t.defined() ? static_cast<int64_t>(t.nbytes()) : int64_t{0};
  };
  int64_t total = nbytes(storage_.obs) + nbytes(storage_.action) + nbytes(storage_.reward) +
                  nbytes(storage_.next_obs) + nbytes(storage_.done) +
                  nbytes(storage_.task_index);
  total += nbytes(batch_.obs) + nbytes(batch_.action) + nbytes(batch_.reward) +
           nbytes(batch_.next_obs) + nbytes(batch_.done) + nbytes(batch_.task_index) +
           nbytes(rows_);
  total += static_cast<int64_t>((size_.capacity() + next_.capacity()) * sizeof(int64_t));
  return total;
}

void ReplayBuffer::Clear() {
  std::fill(size_.begin(), size_.end(), 0);
  std::fill(next_.begin(), next_.end(), 0);
}

void ReplayBuffer::ClearTask(int64_t task) {
  if (task < 0 || task >= num_tasks_) {
    throw Error("ReplayBuffer::ClearTask: task " + std::to_string(task) + " outside [0, " +
                std::to_string(num_tasks_) + ")");
  }
  size_[task] = 0;
  next_[task] = 0;
}

void ReplayBuffer::ResizeBatch(int64_t batch_size) {
  if (batch_.size() == batch_size) return;
  const auto f32 = torch::TensorOptions().dtype(torch::kFloat32);
  batch_.obs = torch::empty({batch_size, obs_dim_}, f32);
  batch_.action = torch::empty({batch_size, action_dim_}, f32);
  batch_.reward = torch::empty({batch_size}, f32);
  batch_.next_obs = torch::empty({batch_size, obs_dim_}, f32);
  batch_.done = torch::empty({batch_size}, f32);
  batch_.task_index = torch::empty({batch_size}, torch::kInt64);
  rows_ = torch::empty({batch_size}, torch::kInt64);
}

const Batch& ReplayBuffer::Sample(int64_t batch_size, ReplaySampling sampling,
                                  at::Generator& generator) {
  if (batch_size < 1) {
    throw Error("ReplayBuffer::Sample: batch_size must be >= 1, got " +
                std::to_string(batch_size));
  }
  const int64_t total = size();
  if (total == 0) throw Error("ReplayBuffer::Sample: the buffer is empty");
  ResizeBatch(batch_size);
  // 53-bit uniforms from the generator; floor(u * n) is uniform on [0, n)
  const torch::Tensor u = torch::rand({batch_size}, generator, torch::kFloat64);
  const double* uniform = u.data_ptr<double>();
  int64_t* rows = rows_.data_ptr<int64_t>();
  auto pick = [](double v, int64_t n) {
    return std::min(static_cast<int64_t>(std::floor(v * static_cast<double>(n))), n - 1);
  };
  if (sampling == ReplaySampling::kBalanced) {
    if (batch_size % num_tasks_ != 0) {
      throw Error("ReplayBuffer::Sample: balanced sampling needs batch_size (" +
                  std::to_string(batch_size) + ") to be a multiple of num_tasks (" +
                  std::to_string(num_tasks_) + ")");
    }
    const int64_t per_task = batch_size / num_tasks_;
    for (int64_t t = 0; t < num_tasks_; ++t) {
      if (size_[t] == 0) {
        throw Error("ReplayBuffer::Sample: balanced sampling but task " + std::to_string(t) +
                    " has no transitions yet");
      }
      for (int64_t j = 0; j < per_task; ++j) {
        const int64_t k = t * per_task + j;
        rows[k] = Row(t, pick(uniform[k], size_[t]));
      }
    }
  } else {
    for (int64_t k = 0; k < batch_size; ++k) {
      int64_t i = pick(uniform[k], total);
      int64_t t = 0;
      while (i >= size_[t]) i -= size_[t++];
      rows[k] = Row(t, i);
    }
  }
  return Gather();
}

const Batch& ReplayBuffer::SampleTasks(std::span<const int64_t> tasks, int64_t per_task,
                                       at::Generator& generator) {
  if (tasks.empty() || per_task < 1) {
    throw Error("ReplayBuffer::SampleTasks: needs at least one task and per_task >= 1, got " +
                std::to_string(tasks.size()) + " tasks and per_task " + std::to_string(per_task));
  }
  for (int64_t t : tasks) {
    if (t < 0 || t >= num_tasks_) {
      throw Error("ReplayBuffer::SampleTasks: task " + std::to_string(t) + " outside [0, " +
                  std::to_string(num_tasks_) + ")");
    }
    if (size_[t] == 0) {
      throw Error("ReplayBuffer::SampleTasks: task " + std::to_string(t) +
                  " has no transitions yet");
    }
  }
  const int64_t batch_size = static_cast<int64_t>(tasks.size()) * per_task;
  ResizeBatch(batch_size);
  const torch::Tensor u = torch::rand({batch_size}, generator, torch::kFloat64);
  const double* uniform = u.data_ptr<double>();
  int64_t* rows = rows_.data_ptr<int64_t>();
  for (size_t i = 0; i < tasks.size(); ++i) {
    const int64_t t = tasks[i];
    const auto n = static_cast<double>(size_[t]);
    for (int64_t j = 0; j < per_task; ++j) {
      const int64_t k = static_cast<int64_t>(i) * per_task + j;
      rows[k] = Row(t, std::min(static_cast<int64_t>(std::floor(uniform[k] * n)), size_[t] - 1));
    }
  }
  return Gather();
}

const Batch& ReplayBuffer::Gather() {
  torch::index_select_out(batch_.obs, storage_.obs, 0, rows_);
  torch::index_select_out(batch_.action, storage_.action, 0, rows_);
  torch::index_select_out(batch_.reward, storage_.reward, 0, rows_);
  torch::index_select_out(batch_.next_obs, storage_.next_obs, 0, rows_);
  torch::index_select_out(batch_.done, storage_.done, 0, rows_);
  torch::index_select_out(batch_.task_index, storage_.task_index, 0, rows_);
  return batch_;
}

void ReplayBuffer::Save(std::ostream& out) const {
  Writer w(out);
  w.Bytes(kMagic.data(), kMagic.size());
  w.Value(kVersion);
  w.Value(kEndianMarker);
  w.Value(obs_dim_);
  w.Value(action_dim_);
  w.Value(num_tasks_);
  w.Value(capacity_per_task_);
  for (int64_t s : size_) w.Value(s);
  for (int64_t n : next_) w.Value(n);
  for (int64_t t = 0; t < num_tasks_; ++t) {
    const int64_t first = Row(t, 0);
    w.Rows(storage_.obs, first, size_[t]);
    w.Rows(storage_.action, first, size_[t]);
    w.Rows(storage_.reward, first, size_[t]);
    w.Rows(storage_.next_obs, first, size_[t]);
    w.Rows(storage_.done, first, size_[t]);
    w.Rows(storage_.task_index, first, size_[t]);
  }
  w.Finish();
}

void ReplayBuffer::Load(std::istream& in) {
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
  const std::array<int64_t, 4> want = {obs_dim_, action_dim_, num_tasks_, capacity_per_task_};
  const std::array<const char*, 4> names = {"obs_dim", "action_dim", "num_tasks",
                                            "capacity_per_task"};
  for (size_t i = 0; i < want.size(); ++i) {
    const auto got = r.Value<int64_t>();
    if (got != want[i]) {
      throw Error(std::string("ReplayBuffer::Load: the snapshot has ") + names[i] + " " +
                  std::to_string(got) + ", this buffer " + std::to_string(want[i]));
    }
  }
  std::vector<int64_t> size(num_tasks_), next(num_tasks_);
  for (auto& s : size) s = r.Value<int64_t>();
  for (auto& n : next) n = r.Value<int64_t>();
  for (int64_t t = 0; t < num_tasks_; ++t) {
    const bool ok = size[t] >= 0 && size[t] <= capacity_per_task_ && next[t] >= 0 &&
                    next[t] < capacity_per_task_ &&
                    (size[t] == capacity_per_task_ || next[t] == size[t]);
    if (!ok) {
      throw Error("ReplayBuffer::Load: the snapshot is corrupt (task " + std::to_string(t) +
                  " has size " + std::to_string(size[t]) + ", next " + std::to_string(next[t]) +
                  ")");
    }
  }
  // read into staging tensors so that a failure leaves this buffer as it was
  std::vector<Storage> staged;
  staged.reserve(num_tasks_);
  for (int64_t t = 0; t < num_tasks_; ++t) {
    Storage s = Allocate(size[t], obs_dim_, action_dim_);
    r.Into(s.obs);
    r.Into(s.action);
    r.Into(s.reward);
    r.Into(s.next_obs);
    r.Into(s.done);
    r.Into(s.task_index);
    staged.push_back(std::move(s));
  }
  r.Finish();
  for (int64_t t = 0; t < num_tasks_; ++t) {
    if (size[t] > 0 && !staged[t].task_index.eq(t).all().item<bool>()) {
      throw Error("ReplayBuffer::Load: the snapshot is corrupt (foreign task index in task " +
                  std::to_string(t) + ")");
    }
  }
  for (int64_t t = 0; t < num_tasks_; ++t) {
    if (size[t] == 0) continue;
    const int64_t first = Row(t, 0);
    storage_.obs.narrow(0, first, size[t]).copy_(staged[t].obs);
    storage_.action.narrow(0, first, size[t]).copy_(staged[t].action);
    storage_.reward.narrow(0, first, size[t]).copy_(staged[t].reward);
    storage_.next_obs.narrow(0, first, size[t]).copy_(staged[t].next_obs);
    storage_.done.narrow(0, first, size[t]).copy_(staged[t].done);
  }
  size_ = std::move(size);
  next_ = std::move(next);
}

void ReplayBuffer::SaveFile(const std::filesystem::path& path) const {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw Error("cannot write replay buffer '" + path.string() + "'");
  try {
    Save(out);
  } catch (const Error& e) {
    throw Error(path.string() + ": " + e.what());
  }
  out.close();  // a full disk shows here at the latest
  if (out.fail()) {
    throw Error("cannot write replay buffer '" + path.string() + "' (disk full or I/O error)");
  }
}

void ReplayBuffer::LoadFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot read replay buffer '" + path.string() + "'");
  try {
    Load(in);
  } catch (const Error& e) {
    throw Error(path.string() + ": " + e.what());
  }
}

}  // namespace manyworlds::agents
