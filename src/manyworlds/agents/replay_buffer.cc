#include "manyworlds/agents/replay_buffer.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <string>

#include "manyworlds/core/error.h"
#include "manyworlds/core/memory.h"

namespace manyworlds::agents {
namespace {

void CheckSize(std::string_view what, size_t got, int64_t want) {
  if (static_cast<int64_t>(got) != want) {
    throw Error("ReplayBuffer::Add: " + std::string(what) + " has " + std::to_string(got) +
                " values, expected " + std::to_string(want));
  }
}

// The transition fields of a Storage or a Batch over `rows` rows, each made
// by make(shape, dtype): float32, task_index int64.
template <typename Rows, typename Make>
Rows MakeRows(int64_t rows, int64_t obs_dim, int64_t action_dim, Make make) {
  Rows r;
  r.obs = make({rows, obs_dim}, torch::kFloat32);
  r.action = make({rows, action_dim}, torch::kFloat32);
  r.reward = make({rows}, torch::kFloat32);
  r.next_obs = make({rows, obs_dim}, torch::kFloat32);
  r.done = make({rows}, torch::kFloat32);
  r.task_index = make({rows}, torch::kInt64);
  return r;
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

ReplayBuffer::Storage ReplayBuffer::Allocate(int64_t rows, int64_t obs_dim, int64_t action_dim,
                                             int64_t pixel_size) {
  Storage storage = MakeRows<Storage>(rows, obs_dim, action_dim,
                                      [](at::IntArrayRef shape, torch::ScalarType dtype) {
                                        return torch::zeros(shape, dtype);
                                      });
  if (pixel_size > 0) {
    storage.pixels = torch::zeros({rows, pixel_size}, torch::kUInt8);
    storage.next_pixels = torch::zeros({rows, pixel_size}, torch::kUInt8);
  }
  return storage;
}

ReplayBuffer::ReplayBuffer(int64_t capacity, int64_t obs_dim, int64_t action_dim,
                           int64_t num_tasks, int64_t pixel_size)
    : obs_dim_(obs_dim), action_dim_(action_dim), num_tasks_(num_tasks), pixel_size_(pixel_size) {
  if (obs_dim < 1 || action_dim < 1 || num_tasks < 1 || pixel_size < 0) {
    throw ConfigError("ReplayBuffer: obs_dim, action_dim and num_tasks must be >= 1 and "
                      "pixel_size >= 0, got " +
                      std::to_string(obs_dim) + ", " + std::to_string(action_dim) + ", " +
                      std::to_string(num_tasks) + ", " + std::to_string(pixel_size));
  }
  if (capacity < num_tasks) {
    throw ConfigError("ReplayBuffer: capacity must be >= num_tasks (" +
                      std::to_string(num_tasks) + "), got " + std::to_string(capacity));
  }
  capacity_per_task_ = capacity / num_tasks;
  // obs, next_obs, action, reward, done as float32, the task index as int64, two frames
  CheckMemoryEstimate(static_cast<double>(capacity_per_task_ * num_tasks) *
                          (4.0 * (2.0 * obs_dim + action_dim + 2.0) + 8.0 + 2.0 * pixel_size),
                      "a replay buffer of " + std::to_string(capacity) + " transitions (obs " +
                          std::to_string(obs_dim) +
                          (pixel_size > 0 ? ", frames of " + std::to_string(pixel_size) + " bytes"
                                          : std::string()) +
                          ")",
                      "replay.capacity");
  storage_ = Allocate(capacity_per_task_ * num_tasks, obs_dim, action_dim, pixel_size);
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
  CheckRow(task, obs, action, next_obs);
  if (pixel_size_ > 0) {
    throw Error("ReplayBuffer::Add: this buffer stores frames (pixel_size " +
                std::to_string(pixel_size_) + "); pass them");
  }
  AddRow(task, obs, action, reward, next_obs, done);
}

void ReplayBuffer::Add(int64_t task, std::span<const float> obs, std::span<const float> action,
                       float reward, std::span<const float> next_obs, bool done,
                       std::span<const uint8_t> pixels, std::span<const uint8_t> next_pixels) {
  CheckRow(task, obs, action, next_obs);
  if (pixel_size_ == 0) throw Error("ReplayBuffer::Add: this buffer stores no frames");
  CheckSize("pixels", pixels.size(), pixel_size_);
  CheckSize("next_pixels", next_pixels.size(), pixel_size_);
  const int64_t row = Row(task, next_[task]);
  std::memcpy(storage_.pixels.data_ptr<uint8_t>() + row * pixel_size_, pixels.data(),
              pixels.size());
  std::memcpy(storage_.next_pixels.data_ptr<uint8_t>() + row * pixel_size_, next_pixels.data(),
              next_pixels.size());
  AddRow(task, obs, action, reward, next_obs, done);
}

void ReplayBuffer::CheckRow(int64_t task, std::span<const float> obs,
                            std::span<const float> action,
                            std::span<const float> next_obs) const {
  if (task < 0 || task >= num_tasks_) {
    throw Error("ReplayBuffer::Add: task " + std::to_string(task) + " is outside [0, " +
                std::to_string(num_tasks_) + ")");
  }
  CheckSize("obs", obs.size(), obs_dim_);
  CheckSize("action", action.size(), action_dim_);
  CheckSize("next_obs", next_obs.size(), obs_dim_);
}

void ReplayBuffer::AddRow(int64_t task, std::span<const float> obs, std::span<const float> action,
                          float reward, std::span<const float> next_obs, bool done) {
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
         static_cast<int64_t>(sizeof(int64_t)) + 2 * pixel_size_;
}

int64_t ReplayBuffer::bytes() const {
  auto nbytes = [](const torch::Tensor& t) {
    return t.defined() ? static_cast<int64_t>(t.nbytes()) : int64_t{0};
  };
  int64_t total = nbytes(storage_.obs) + nbytes(storage_.action) + nbytes(storage_.reward) +
                  nbytes(storage_.next_obs) + nbytes(storage_.done) +
                  nbytes(storage_.task_index) + nbytes(storage_.pixels) +
                  nbytes(storage_.next_pixels);
  total += nbytes(batch_.pixels) + nbytes(batch_.next_pixels) + nbytes(batch_.obs) + nbytes(batch_.action) + nbytes(batch_.reward) +
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
  batch_ = MakeRows<Batch>(batch_size, obs_dim_, action_dim_,
                           [](at::IntArrayRef shape, torch::ScalarType dtype) {
                             return torch::empty(shape, dtype);
                           });
  if (pixel_size_ > 0) {
    batch_.pixels = torch::empty({batch_size, pixel_size_}, torch::kUInt8);
    batch_.next_pixels = torch::empty({batch_size, pixel_size_}, torch::kUInt8);
  }
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
  if (pixel_size_ > 0) {
    torch::index_select_out(batch_.pixels, storage_.pixels, 0, rows_);
    torch::index_select_out(batch_.next_pixels, storage_.next_pixels, 0, rows_);
  }
  return batch_;
}

ReplayShape ReplayBuffer::shape() const {
  return {obs_dim_, action_dim_, num_tasks_, capacity_per_task_};
}

void ReplayBuffer::Save(std::ostream& out) const {
  std::vector<ReplayTaskView> tasks(static_cast<size_t>(num_tasks_));
  for (int64_t t = 0; t < num_tasks_; ++t) {
    const int64_t first = Row(t, 0);
    ReplayTaskView& view = tasks[t];
    view.size = size_[t];
    view.next = next_[t];
    view.obs = storage_.obs.data_ptr<float>() + first * obs_dim_;
    view.action = storage_.action.data_ptr<float>() + first * action_dim_;
    view.reward = storage_.reward.data_ptr<float>() + first;
    view.next_obs = storage_.next_obs.data_ptr<float>() + first * obs_dim_;
    view.done = storage_.done.data_ptr<float>() + first;
    view.task_index = storage_.task_index.data_ptr<int64_t>() + first;
  }
  WriteReplaySnapshot(out, shape(), tasks);
  if (pixel_size_ > 0) SavePixels(out);
}

void ReplayBuffer::SavePixels(std::ostream& out) const {
  std::vector<ReplayTaskFramesView> tasks(static_cast<size_t>(num_tasks_));
  for (int64_t t = 0; t < num_tasks_; ++t) {
    const int64_t first = Row(t, 0) * pixel_size_;
    tasks[t] = {size_[t], storage_.pixels.data_ptr<uint8_t>() + first,
                storage_.next_pixels.data_ptr<uint8_t>() + first};
  }
  WriteReplayFrames(out, pixel_size_, tasks);
}

void ReplayBuffer::Load(std::istream& in) {
  // everything is read and checked before this buffer changes
  const std::vector<ReplayTaskRows> tasks = ReadReplaySnapshot(in, shape());
  std::vector<ReplayTaskFrames> frames;
  if (pixel_size_ > 0) {
    std::vector<int64_t> sizes;
    for (const ReplayTaskRows& task : tasks) sizes.push_back(task.size);
    frames = ReadReplayFrames(in, pixel_size_, sizes);
  }
  auto copy = [](const std::vector<float>& from, torch::Tensor& to, int64_t offset) {
    if (!from.empty()) {
      std::memcpy(to.data_ptr<float>() + offset, from.data(), from.size() * sizeof(float));
    }
  };
  for (int64_t t = 0; t < num_tasks_; ++t) {
    const ReplayTaskRows& task = tasks[t];
    const int64_t first = Row(t, 0);
    copy(task.obs, storage_.obs, first * obs_dim_);
    copy(task.action, storage_.action, first * action_dim_);
    copy(task.reward, storage_.reward, first);
    copy(task.next_obs, storage_.next_obs, first * obs_dim_);
    copy(task.done, storage_.done, first);
    if (pixel_size_ > 0) {
      const ReplayTaskFrames& task_frames = frames[static_cast<size_t>(t)];
      for (const auto& [rows, to] : {std::pair(&task_frames.pixels, &storage_.pixels),
                                     std::pair(&task_frames.next_pixels, &storage_.next_pixels)}) {
        if (!rows->empty()) {
          std::memcpy(to->data_ptr<uint8_t>() + first * pixel_size_, rows->data(), rows->size());
        }
      }
    }
    size_[t] = task.size;
    next_[t] = task.next;
  }
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
