#include "manyworlds/core/executor.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <string>
#include <thread>

#include "manyworlds/core/error.h"
#include "manyworlds/core/limits.h"
#include "manyworlds/core/rng.h"

// Threading design.
//
// num_threads == 1, Step/Reset: the calling thread steps every env in a plain
// loop; no atomics, no handoff.
//
// num_threads == T > 1, Step/Reset: T - 1 persistent workers plus the calling
// thread. A job is published by writing its description and then one 64-bit
// claim word (job id << 32 | next env index) with release order. Every
// participant claims chunks of env indices with a CAS on that word, so each
// env is stepped by exactly one thread and a late worker can never claim
// from a job that is already finished (the job id in the word differs). The
// thread whose chunk completes the batch wakes the caller.
//
// Send/Recv: T workers (for T == 1, one background worker) run the job while
// the caller is free; the worker with index T - 1 is started on the first
// Send, so sync-only users never pay for it.
//
// Waiting is spin-then-block: a short pause loop, then std::atomic::wait
// (a futex on Linux; notify is nearly free when nobody sleeps).
//
// Results never depend on the thread count because an env's step only reads
// its own state and action row and only writes its own output rows.
//
// Details the header leaves open: num_threads() reports min(num_threads,
// num_envs), since more threads than envs would only idle; final_* rows of
// envs that did not end in the last step keep older values; an env that
// throws does not stop the others of the batch, so the batch advances the
// same way for every thread count.

namespace manyworlds {
namespace {

// Pause iterations before blocking. Workers spin a few tens of microseconds,
// long enough to bridge a cheap policy call between steps, short enough not
// to burn a shared core. A caller waiting in Recv has nothing to do, so it
// blocks soon and leaves the cores to the workers.
constexpr int kWorkerSpin = 2000;
constexpr int kCallerSyncSpin = 2000;
constexpr int kCallerAsyncSpin = 100;

inline void CpuRelax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#elif defined(__aarch64__)
  asm volatile("yield");
#else
  std::this_thread::yield();
#endif
}

// Waits until `value` differs from `old` and returns the new value.
template <typename T>
T SpinThenWaitChange(const std::atomic<T>& value, T old, int spin) {
  for (int i = 0; i < spin; ++i) {
    const T now = value.load(std::memory_order_acquire);
    if (now != old) return now;
    CpuRelax();
  }
  for (;;) {
    value.wait(old, std::memory_order_acquire);
    const T now = value.load(std::memory_order_acquire);
    if (now != old) return now;
  }
}

constexpr size_t kCacheLine = 64;

struct alignas(kCacheLine) WorkerSlot {
  std::atomic<uint32_t> wake{0};
};

}  // namespace

struct BatchedExecutor::Impl {
  enum class JobKind { kStep, kReset };

  Impl(std::vector<std::unique_ptr<Env>> env_list, ExecutorOptions opts);
  ~Impl();

  // Per-env work; exceptions are the caller's business.
  void StepEnv(int i, const float* actions);
  void ResetEnv(int i);
  // Runs envs [begin, end) of the current job, storing exceptions per env.
  // Returns true if one was stored.
  bool RunRange(int begin, int end);
  // Claims chunks of the published job until none is left.
  void RunClaims();
  void WorkerLoop(int index);
  void StartWorker(int index);
  // Publishes a job to workers [0, num_workers).
  void Launch(JobKind kind, const float* actions, int num_workers);
  void WaitDone(int spin) const;
  void RethrowFirstError();
  // Runs a sync job on the calling thread (and workers if T > 1).
  void RunSync(JobKind kind, const float* actions);
  void CheckNotPending(const char* what) const;
  void CheckActions(std::span<const float> actions) const;

  std::vector<std::unique_ptr<Env>> envs;
  ExecutorOptions options;
  int n = 0;        // number of envs
  int threads = 1;  // effective thread count, <= n
  int64_t action_size = 0;
  int64_t env_obs_size = 0;
  int64_t task_obs_size = 0;
  int64_t info_size = 0;
  int64_t pixels_size = 0;
  std::vector<std::string> info_fields;

  // Output buffers, one row per env.
  std::vector<float> env_obs, task_obs, rewards, info, final_env_obs, final_task_obs;
  std::vector<uint8_t> pixels, final_pixels;  // empty without pixel observations
  std::unique_ptr<bool[]> terminated, truncated;
  std::vector<int64_t> episode_steps;
  // Action copy for Send.
  std::vector<float> send_actions;
  // First exception of each env in the current job.
  std::vector<std::exception_ptr> errors;

  // Current job (written by the owner before the claim word is published).
  JobKind job_kind = JobKind::kStep;
  const float* job_actions = nullptr;
  int chunk = 1;
  uint32_t job_id = 0;
  bool pending = false;  // a Send awaits its Recv

  alignas(kCacheLine) std::atomic<uint64_t> claim{0};
  alignas(kCacheLine) std::atomic<int> completed{0};
  std::atomic<bool> has_error{false};
  alignas(kCacheLine) std::atomic<bool> stop{false};
  std::unique_ptr<WorkerSlot[]> slots;  // one per potential worker (threads)
  std::vector<std::thread> workers;
};

BatchedExecutor::Impl::Impl(std::vector<std::unique_ptr<Env>> env_list, ExecutorOptions opts)
    : envs(std::move(env_list)), options(opts) {
  if (envs.empty()) throw ConfigError("BatchedExecutor: needs at least one env, got none");
  if (options.num_threads < 1) {
    throw ConfigError("BatchedExecutor: num_threads must be >= 1, got " +
                      std::to_string(options.num_threads));
  }
  if (options.num_threads > kMaxThreads) {
    throw ConfigError("BatchedExecutor: num_threads must be at most " +
                      std::to_string(kMaxThreads) + ", got " + std::to_string(options.num_threads));
  }
  if (envs.size() > static_cast<size_t>(kMaxEnvs)) {
    throw ConfigError("BatchedExecutor: at most " + std::to_string(kMaxEnvs) + " envs, got " +
                      std::to_string(envs.size()));
  }
  for (size_t i = 0; i < envs.size(); ++i) {
    if (!envs[i]) throw ConfigError("BatchedExecutor: env " + std::to_string(i) + " is null");
  }
  const EnvSpec& first = envs[0]->spec();
  action_size = first.action_space.flat_size();
  env_obs_size = first.env_obs_space.flat_size();
  task_obs_size = first.task_obs_space.flat_size();
  pixels_size = first.pixel_space.flat_size();
  info_fields = first.info_fields;
  info_size = static_cast<int64_t>(info_fields.size());
  for (size_t i = 1; i < envs.size(); ++i) {
    const EnvSpec& spec = envs[i]->spec();
    auto mismatch = [&](const std::string& what, const std::string& got, const std::string& want) {
      throw ConfigError("BatchedExecutor: env " + std::to_string(i) + " ('" + spec.id + "') has " +
                        what + " " + got + ", env 0 ('" + first.id + "') has " + want +
                        "; all envs of a batch need the same sizes and info fields");
    };
    if (spec.action_space.flat_size() != action_size) {
      mismatch("action size", std::to_string(spec.action_space.flat_size()),
               std::to_string(action_size));
    }
    if (spec.env_obs_space.flat_size() != env_obs_size) {
      mismatch("env_obs size", std::to_string(spec.env_obs_space.flat_size()),
               std::to_string(env_obs_size));
    }
    if (spec.task_obs_space.flat_size() != task_obs_size) {
      mismatch("task_obs size", std::to_string(spec.task_obs_space.flat_size()),
               std::to_string(task_obs_size));
    }
    if (spec.pixel_space.flat_size() != pixels_size) {
      mismatch("pixel observation size", std::to_string(spec.pixel_space.flat_size()),
               std::to_string(pixels_size));
    }
    if (spec.info_fields != info_fields) {
      auto join = [](const std::vector<std::string>& v) {
        std::string s = "[";
        for (size_t k = 0; k < v.size(); ++k) s += (k ? ", " : "") + v[k];
        return s + "]";
      };
      mismatch("info fields", join(spec.info_fields), join(info_fields));
    }
  }

  n = static_cast<int>(envs.size());
  // More threads than envs would only idle.
  threads = std::min(options.num_threads, n);
  const size_t rows = static_cast<size_t>(n);
  env_obs.assign(rows * env_obs_size, 0.0f);
  task_obs.assign(rows * task_obs_size, 0.0f);
  final_env_obs.assign(rows * env_obs_size, 0.0f);
  final_task_obs.assign(rows * task_obs_size, 0.0f);
  pixels.assign(rows * pixels_size, 0);
  final_pixels.assign(rows * pixels_size, 0);
  rewards.assign(rows, 0.0f);
  info.assign(rows * info_size, 0.0f);
  terminated = std::make_unique<bool[]>(rows);  // value-initialised: false
  truncated = std::make_unique<bool[]>(rows);
  episode_steps.assign(rows, 0);
  send_actions.assign(rows * action_size, 0.0f);
  errors.resize(rows);
  // Several chunks per thread balance envs of unequal cost; one claim per
  // chunk keeps contention on the claim word low for cheap envs.
  chunk = std::max(1, n / (8 * threads));

  slots = std::make_unique<WorkerSlot[]>(threads);
  workers.reserve(threads);
  try {
    for (int w = 0; w + 1 < threads; ++w) StartWorker(w);
  } catch (const std::exception& e) {
    stop.store(true);
    for (size_t w = 0; w < workers.size(); ++w) {
      slots[w].wake.fetch_add(1, std::memory_order_release);
      slots[w].wake.notify_one();
      workers[w].join();
    }
    ThrowThreadsNotStarted(e, static_cast<int64_t>(workers.size()) + 1, threads,
                           "the number of worker threads");
  }
}

BatchedExecutor::Impl::~Impl() {
  if (pending) WaitDone(kCallerAsyncSpin);
  stop.store(true, std::memory_order_release);
  for (size_t w = 0; w < workers.size(); ++w) {
    slots[w].wake.fetch_add(1, std::memory_order_release);
    slots[w].wake.notify_one();
  }
  for (auto& worker : workers) worker.join();
}

void BatchedExecutor::Impl::StartWorker(int index) {
  workers.emplace_back([this, index] { WorkerLoop(index); });
}

void BatchedExecutor::Impl::WorkerLoop(int index) {
  std::atomic<uint32_t>& wake = slots[index].wake;
  // Slots start at 0 and a worker starts before its first job: a job
  // published before this thread got to run is still seen as new.
  uint32_t seen = 0;
  for (;;) {
    seen = SpinThenWaitChange(wake, seen, kWorkerSpin);
    if (stop.load(std::memory_order_acquire)) return;
    RunClaims();
  }
}

inline void BatchedExecutor::Impl::StepEnv(int i, const float* actions) {
  const size_t row = static_cast<size_t>(i);
  float* eo = env_obs.data() + row * env_obs_size;
  float* to = task_obs.data() + row * task_obs_size;
  const std::span<uint8_t> px(pixels.data() + row * pixels_size, pixels_size);
  Env& env = *envs[row];
  env.Step(std::span<const float>(actions + row * action_size, action_size),
           StepView{std::span<float>(eo, env_obs_size), std::span<float>(to, task_obs_size),
                    &rewards[row], &terminated[row], &truncated[row],
                    std::span<float>(info.data() + row * info_size, info_size), px});
  if (options.auto_reset && (terminated[row] || truncated[row])) {
    // Keep the last observation, then start the next episode in place.
    std::copy_n(eo, env_obs_size, final_env_obs.data() + row * env_obs_size);
    std::copy_n(to, task_obs_size, final_task_obs.data() + row * task_obs_size);
    std::copy_n(px.data(), pixels_size, final_pixels.data() + row * pixels_size);
    episode_steps[row] = 0;
    env.Reset(ObsView{std::span<float>(eo, env_obs_size), std::span<float>(to, task_obs_size),
                      px});
    return;
  }
  episode_steps[row] = env.elapsed_steps();
}

void BatchedExecutor::Impl::ResetEnv(int i) {
  const size_t row = static_cast<size_t>(i);
  rewards[row] = 0.0f;
  terminated[row] = false;
  truncated[row] = false;
  std::fill_n(info.data() + row * info_size, info_size, 0.0f);
  episode_steps[row] = 0;
  envs[row]->Reset(ObsView{std::span<float>(env_obs.data() + row * env_obs_size, env_obs_size),
                           std::span<float>(task_obs.data() + row * task_obs_size, task_obs_size),
                           std::span<uint8_t>(pixels.data() + row * pixels_size, pixels_size)});
}

bool BatchedExecutor::Impl::RunRange(int begin, int end) {
  bool failed = false;
  // Every env of the range runs even if one throws, so that the batch
  // advances the same way whatever the thread count.
  if (job_kind == JobKind::kStep) {
    for (int i = begin; i < end; ++i) {
      try {
        StepEnv(i, job_actions);
      } catch (...) {
        errors[i] = std::current_exception();
        failed = true;
      }
    }
  } else {
    for (int i = begin; i < end; ++i) {
      try {
        ResetEnv(i);
      } catch (...) {
        errors[i] = std::current_exception();
        failed = true;
      }
    }
  }
  return failed;
}

void BatchedExecutor::Impl::RunClaims() {
  uint64_t word = claim.load(std::memory_order_acquire);
  for (;;) {
    const uint32_t begin = static_cast<uint32_t>(word);
    if (begin >= static_cast<uint32_t>(n)) return;
    const uint32_t end = std::min<uint32_t>(begin + chunk, n);
    const uint64_t next = (word & ~uint64_t{0xffffffff}) | end;
    if (!claim.compare_exchange_weak(word, next, std::memory_order_acq_rel,
                                     std::memory_order_acquire)) {
      continue;  // word now holds the current value
    }
    if (RunRange(static_cast<int>(begin), static_cast<int>(end))) {
      has_error.store(true, std::memory_order_relaxed);
    }
    const int count = static_cast<int>(end - begin);
    // acq_rel: publishes this chunk's rows (and errors) to whoever sees n.
    if (completed.fetch_add(count, std::memory_order_acq_rel) + count == n) {
      completed.notify_all();
    }
    word = next;
  }
}

void BatchedExecutor::Impl::Launch(JobKind kind, const float* actions, int num_workers) {
  job_kind = kind;
  job_actions = actions;
  completed.store(0, std::memory_order_relaxed);
  has_error.store(false, std::memory_order_relaxed);
  ++job_id;
  claim.store(static_cast<uint64_t>(job_id) << 32, std::memory_order_release);
  for (int w = 0; w < num_workers; ++w) {
    slots[w].wake.fetch_add(1, std::memory_order_release);
    slots[w].wake.notify_one();
  }
}

void BatchedExecutor::Impl::WaitDone(int spin) const {
  int now = completed.load(std::memory_order_acquire);
  while (now != n) now = SpinThenWaitChange(completed, now, spin);
}

void BatchedExecutor::Impl::RethrowFirstError() {
  std::exception_ptr first;
  for (auto& error : errors) {
    if (error && !first) first = error;
    error = nullptr;
  }
  if (first) std::rethrow_exception(first);
}

void BatchedExecutor::Impl::RunSync(JobKind kind, const float* actions) {
  if (threads == 1) {
    job_kind = kind;
    job_actions = actions;
    if (RunRange(0, n)) RethrowFirstError();
    return;
  }
  Launch(kind, actions, threads - 1);
  RunClaims();
  WaitDone(kCallerSyncSpin);
  if (has_error.load(std::memory_order_relaxed)) RethrowFirstError();
}

void BatchedExecutor::Impl::CheckNotPending(const char* what) const {
  if (pending) {
    throw EpisodeStateError(std::string("BatchedExecutor: ") + what +
                            " called while a Send awaits its Recv; call Recv first");
  }
}

void BatchedExecutor::Impl::CheckActions(std::span<const float> actions) const {
  const size_t want = static_cast<size_t>(n) * action_size;
  if (actions.size() != want) {
    throw InvalidActionError("BatchedExecutor: action buffer has " +
                             std::to_string(actions.size()) + " values, expected " +
                             std::to_string(want) + " (num_envs " + std::to_string(n) +
                             " x action_size " + std::to_string(action_size) + ")");
  }
}

BatchedExecutor::BatchedExecutor(std::vector<std::unique_ptr<Env>> envs, ExecutorOptions options)
    : impl_(std::make_unique<Impl>(std::move(envs), options)) {}

BatchedExecutor::~BatchedExecutor() = default;

int BatchedExecutor::num_envs() const { return impl_->n; }
int BatchedExecutor::num_threads() const { return impl_->threads; }
int64_t BatchedExecutor::action_size() const { return impl_->action_size; }
int64_t BatchedExecutor::env_obs_size() const { return impl_->env_obs_size; }
int64_t BatchedExecutor::task_obs_size() const { return impl_->task_obs_size; }
const std::vector<std::string>& BatchedExecutor::info_fields() const { return impl_->info_fields; }

Env& BatchedExecutor::env(int index) {
  if (index < 0 || index >= impl_->n) {
    throw Error("BatchedExecutor: env index " + std::to_string(index) + " out of range [0, " +
                std::to_string(impl_->n) + ")");
  }
  return *impl_->envs[index];
}

void BatchedExecutor::Seed(uint64_t env_seed, uint64_t task_seed) {
  impl_->CheckNotPending("Seed");
  for (int i = 0; i < impl_->n; ++i) {
    impl_->envs[i]->Seed(MixSeed(env_seed, static_cast<uint64_t>(i)));
    impl_->envs[i]->SeedTask(MixSeed(task_seed, static_cast<uint64_t>(i)));
  }
}

void BatchedExecutor::SetTaskState(int index, const TaskState& state) {
  impl_->CheckNotPending("SetTaskState");
  env(index).SetTaskState(state);
  impl_->ResetEnv(index);
}

void BatchedExecutor::ResetEnv(int index) {
  impl_->CheckNotPending("ResetEnv");
  env(index);  // checks the index
  impl_->ResetEnv(index);
}

void BatchedExecutor::Reset() {
  impl_->CheckNotPending("Reset");
  impl_->RunSync(Impl::JobKind::kReset, nullptr);
}

void BatchedExecutor::Step(std::span<const float> actions) {
  impl_->CheckNotPending("Step");
  impl_->CheckActions(actions);
  // The caller's buffer outlives the sync job, so no copy is needed.
  impl_->RunSync(Impl::JobKind::kStep, actions.data());
}

void BatchedExecutor::Send(std::span<const float> actions) {
  Impl& m = *impl_;
  if (m.pending) {
    throw EpisodeStateError("BatchedExecutor: Send called twice without Recv");
  }
  m.CheckActions(actions);
  std::copy(actions.begin(), actions.end(), m.send_actions.begin());
  // The worker that replaces the caller's share starts on first use.
  if (static_cast<int>(m.workers.size()) < m.threads) m.StartWorker(m.threads - 1);
  m.Launch(Impl::JobKind::kStep, m.send_actions.data(), m.threads);
  m.pending = true;
}

void BatchedExecutor::Recv() {
  Impl& m = *impl_;
  if (!m.pending) throw EpisodeStateError("BatchedExecutor: Recv called without a pending Send");
  m.WaitDone(kCallerAsyncSpin);
  m.pending = false;
  if (m.has_error.load(std::memory_order_relaxed)) m.RethrowFirstError();
}

std::span<const float> BatchedExecutor::env_obs() const { return impl_->env_obs; }
std::span<const float> BatchedExecutor::task_obs() const { return impl_->task_obs; }
std::span<const float> BatchedExecutor::rewards() const { return impl_->rewards; }
std::span<const bool> BatchedExecutor::terminated() const {
  return {impl_->terminated.get(), static_cast<size_t>(impl_->n)};
}
std::span<const bool> BatchedExecutor::truncated() const {
  return {impl_->truncated.get(), static_cast<size_t>(impl_->n)};
}
std::span<const float> BatchedExecutor::info() const { return impl_->info; }
std::span<const float> BatchedExecutor::final_env_obs() const { return impl_->final_env_obs; }
std::span<const float> BatchedExecutor::final_task_obs() const { return impl_->final_task_obs; }
int64_t BatchedExecutor::pixels_size() const { return impl_->pixels_size; }
std::span<const uint8_t> BatchedExecutor::pixels() const { return impl_->pixels; }
std::span<const uint8_t> BatchedExecutor::final_pixels() const { return impl_->final_pixels; }
std::span<const int64_t> BatchedExecutor::episode_steps() const { return impl_->episode_steps; }

}  // namespace manyworlds
