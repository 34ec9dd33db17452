#include "manyworlds/agents/replay_buffer.h"

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <gtest/gtest.h>
#include <torch/torch.h>

#include "manyworlds/core/error.h"

namespace manyworlds::agents {
namespace {

// Transition k of task t: obs = (t, k, ...), action = k / 1000, reward = k,
// next_obs = obs + 1, done every 7th.
void AddTransition(ReplayBuffer& replay, int64_t task, int k) {
  std::vector<float> obs(replay.obs_dim(), static_cast<float>(k));
  obs[0] = static_cast<float>(task);
  std::vector<float> next = obs;
  for (float& v : next) v += 1.0f;
  std::vector<float> action(replay.action_dim(), static_cast<float>(k) / 1000.0f);
  replay.Add(task, obs, action, static_cast<float>(k), next, k % 7 == 0);
}

at::Generator Gen(uint64_t seed) { return at::detail::createCPUGenerator(seed); }

TEST(ReplayBufferTest, PartitionsSplitCapacityAndRingPerTask) {
  ReplayBuffer replay(10, 3, 2, 3);  // 3 rows per task, one unused
  EXPECT_EQ(replay.capacity_per_task(), 3);
  EXPECT_EQ(replay.capacity(), 9);
  for (int k = 0; k < 5; ++k) AddTransition(replay, 0, k);  // task 0 wraps
  AddTransition(replay, 2, 100);
  EXPECT_EQ(replay.size(0), 3);
  EXPECT_EQ(replay.size(1), 0);
  EXPECT_EQ(replay.size(2), 1);
  EXPECT_EQ(replay.size(), 4);

  // task 0 holds k = 2, 3, 4 (0 and 1 overwritten); task 1 nothing
  auto gen = Gen(1);
  const Batch& b = replay.Sample(200, ReplaySampling::kUniform, gen);
  std::vector<int> seen(5, 0);
  int task2 = 0;
  for (int64_t i = 0; i < b.size(); ++i) {
    const int64_t task = b.task_index[i].item<int64_t>();
    ASSERT_NE(task, 1);
    EXPECT_FLOAT_EQ(b.obs[i][0].item<float>(), static_cast<float>(task));
    const int k = static_cast<int>(b.reward[i].item<float>());
    EXPECT_FLOAT_EQ(b.next_obs[i][1].item<float>(), static_cast<float>(k) + 1.0f);
    EXPECT_FLOAT_EQ(b.action[i][0].item<float>(), static_cast<float>(k) / 1000.0f);
    EXPECT_FLOAT_EQ(b.done[i].item<float>(), k % 7 == 0 ? 1.0f : 0.0f);
    if (task == 0) {
      ASSERT_GE(k, 2);
      ++seen[k];
    } else {
      EXPECT_EQ(k, 100);
      ++task2;
    }
  }
  EXPECT_GT(seen[2], 0);
  EXPECT_GT(seen[3], 0);
  EXPECT_GT(seen[4], 0);
  // uniform over the 4 stored transitions: task 2 gets about a quarter
  EXPECT_GT(task2, 25);
  EXPECT_LT(task2, 80);
}

TEST(ReplayBufferTest, BalancedSamplingGivesEqualCountsPerTask) {
  ReplayBuffer replay(3000, 4, 2, 3);
  // very unequal fill: 1000, 10 and 1 transitions
  for (int k = 0; k < 1000; ++k) AddTransition(replay, 0, k);
  for (int k = 0; k < 10; ++k) AddTransition(replay, 1, k);
  AddTransition(replay, 2, 0);
  auto gen = Gen(2);
  const Batch& b = replay.Sample(96, ReplaySampling::kBalanced, gen);
  const torch::Tensor counts = torch::bincount(b.task_index, {}, 3);
  EXPECT_EQ(counts[0].item<int64_t>(), 32);
  EXPECT_EQ(counts[1].item<int64_t>(), 32);
  EXPECT_EQ(counts[2].item<int64_t>(), 32);
  // rows match their task
  EXPECT_TRUE(b.obs.select(1, 0).to(torch::kInt64).equal(b.task_index));

  // uniform sampling instead follows the stored amounts
  const Batch& u = replay.Sample(1011, ReplaySampling::kUniform, gen);
  const torch::Tensor ucounts = torch::bincount(u.task_index, {}, 3);
  EXPECT_GT(ucounts[0].item<int64_t>(), 950);

  EXPECT_THROW(replay.Sample(100, ReplaySampling::kBalanced, gen), Error);  // not a multiple
  ReplayBuffer partial(30, 4, 2, 3);
  AddTransition(partial, 0, 1);
  EXPECT_THROW(partial.Sample(3, ReplaySampling::kBalanced, gen), Error);  // task 1 empty
  EXPECT_NO_THROW(partial.Sample(3, ReplaySampling::kUniform, gen));
  ReplayBuffer empty(30, 4, 2, 3);
  EXPECT_THROW(empty.Sample(3, ReplaySampling::kUniform, gen), Error);
  EXPECT_THROW(empty.Sample(0, ReplaySampling::kUniform, gen), Error);
}

TEST(ReplayBufferTest, SampleTasksGroupsRowsByTheListedTasks) {
  ReplayBuffer replay(300, 4, 2, 3);
  for (int k = 0; k < 50; ++k) AddTransition(replay, 0, k);
  for (int k = 0; k < 5; ++k) AddTransition(replay, 2, k);
  auto gen = Gen(4);
  const std::vector<int64_t> tasks = {2, 0, 2};
  const Batch& b = replay.SampleTasks(tasks, 8, gen);
  ASSERT_EQ(b.size(), 24);
  for (int64_t i = 0; i < 24; ++i) {
    EXPECT_EQ(b.task_index[i].item<int64_t>(), tasks[i / 8]) << i;
    EXPECT_EQ(b.obs[i][0].item<float>(), static_cast<float>(tasks[i / 8])) << i;
  }
  EXPECT_LT(b.reward.narrow(0, 0, 8).max().item<float>(), 5.0f);  // task 2 holds k < 5
  const std::vector<int64_t> empty_task = {1};
  EXPECT_THROW(replay.SampleTasks(empty_task, 4, gen), Error);
  const std::vector<int64_t> outside = {3};
  EXPECT_THROW(replay.SampleTasks(outside, 4, gen), Error);
  EXPECT_THROW(replay.SampleTasks(tasks, 0, gen), Error);

  // clearing one task forgets it alone
  replay.ClearTask(2);
  EXPECT_EQ(replay.size(2), 0);
  EXPECT_EQ(replay.size(0), 50);
  EXPECT_THROW(replay.SampleTasks(tasks, 4, gen), Error);
  AddTransition(replay, 2, 42);
  const std::vector<int64_t> two = {2};
  EXPECT_EQ(replay.SampleTasks(two, 3, gen).reward.min().item<float>(), 42.0f);
  EXPECT_THROW(replay.ClearTask(-1), Error);
}

TEST(ReplayBufferTest, SamplingIsDeterministicGivenTheGenerator) {
  ReplayBuffer replay(100, 3, 1, 2);
  for (int k = 0; k < 50; ++k) AddTransition(replay, k % 2, k);
  auto g1 = Gen(9);
  auto g2 = Gen(9);
  const torch::Tensor a = replay.Sample(16, ReplaySampling::kUniform, g1).reward.clone();
  const torch::Tensor b = replay.Sample(16, ReplaySampling::kUniform, g2).reward.clone();
  EXPECT_TRUE(a.equal(b));
  const torch::Tensor c = replay.Sample(16, ReplaySampling::kUniform, g1).reward.clone();
  EXPECT_FALSE(a.equal(c));
}

TEST(ReplayBufferTest, BatchTensorsAreReusedAcrossSamples) {
  ReplayBuffer replay(100, 3, 1, 1);
  for (int k = 0; k < 10; ++k) AddTransition(replay, 0, k);
  auto gen = Gen(3);
  const void* first = replay.Sample(8, ReplaySampling::kUniform, gen).obs.data_ptr();
  const void* second = replay.Sample(8, ReplaySampling::kUniform, gen).obs.data_ptr();
  EXPECT_EQ(first, second);
}

TEST(ReplayBufferTest, MemoryStaysWithinTenPercentOfRawTransitionBytes) {
  // MT10-like: 39-dim obs, 4-dim actions, 10 tasks
  ReplayBuffer replay(100000, 39, 4, 10);
  const int64_t raw = replay.capacity() * replay.transition_bytes();
  EXPECT_EQ(replay.transition_bytes(), 4 * (2 * 39 + 4 + 2) + 8);
  EXPECT_GE(replay.bytes(), raw);
  EXPECT_LE(static_cast<double>(replay.bytes()), 1.1 * static_cast<double>(raw));
  for (int k = 0; k < 20; ++k) AddTransition(replay, k % 10, k);
  auto gen = Gen(4);
  replay.Sample(1280, ReplaySampling::kBalanced, gen);
  EXPECT_LE(static_cast<double>(replay.bytes()), 1.1 * static_cast<double>(raw));
}

TEST(ReplayBufferTest, SaveLoadRoundTripRestoresContentsAndRingPositions) {
  ReplayBuffer replay(12, 3, 2, 3);
  for (int k = 0; k < 6; ++k) AddTransition(replay, 0, k);  // wrapped
  for (int k = 0; k < 2; ++k) AddTransition(replay, 1, 10 + k);
  std::stringstream snapshot;
  replay.Save(snapshot);

  ReplayBuffer restored(12, 3, 2, 3);
  AddTransition(restored, 2, 99);  // replaced by the load
  restored.Load(snapshot);
  EXPECT_EQ(restored.size(0), 4);
  EXPECT_EQ(restored.size(1), 2);
  EXPECT_EQ(restored.size(2), 0);
  auto g1 = Gen(5);
  auto g2 = Gen(5);
  const Batch& a = replay.Sample(64, ReplaySampling::kUniform, g1);
  const Batch& b = restored.Sample(64, ReplaySampling::kUniform, g2);
  EXPECT_TRUE(a.obs.equal(b.obs));
  EXPECT_TRUE(a.action.equal(b.action));
  EXPECT_TRUE(a.reward.equal(b.reward));
  EXPECT_TRUE(a.next_obs.equal(b.next_obs));
  EXPECT_TRUE(a.done.equal(b.done));
  EXPECT_TRUE(a.task_index.equal(b.task_index));
  // ring positions too: the next add overwrites the same slot in both
  AddTransition(replay, 0, 50);
  AddTransition(restored, 0, 50);
  std::stringstream s1, s2;
  replay.Save(s1);
  restored.Save(s2);
  EXPECT_EQ(s1.str(), s2.str());
}

TEST(ReplayBufferTest, CorruptOrMismatchedSnapshotsFailClearlyAndChangeNothing) {
  ReplayBuffer replay(12, 3, 2, 3);
  for (int k = 0; k < 5; ++k) AddTransition(replay, k % 3, k);
  std::stringstream snapshot;
  replay.Save(snapshot);
  const std::string bytes = snapshot.str();

  auto expect_error = [&](const std::string& data, ReplayBuffer& target, const char* needle) {
    std::stringstream in(data);
    try {
      target.Load(in);
      ADD_FAILURE() << "no error for " << needle;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  ReplayBuffer target(12, 3, 2, 3);
  AddTransition(target, 1, 42);
  std::string flipped = bytes;
  flipped[flipped.size() / 2] ^= 0x10;
  expect_error(flipped, target, "checksum");
  expect_error(bytes.substr(0, bytes.size() - 20), target, "truncated");
  expect_error("not a replay buffer at all", target, "not a replay buffer");
  expect_error("", target, "truncated");
  ReplayBuffer other_dims(12, 4, 2, 3);
  expect_error(bytes, other_dims, "obs_dim");
  ReplayBuffer other_tasks(12, 3, 2, 2);
  expect_error(bytes, other_tasks, "num_tasks");
  // target kept its single transition
  EXPECT_EQ(target.size(), 1);
  EXPECT_EQ(target.size(1), 1);

  // files: the path is named
  const auto path = std::filesystem::temp_directory_path() / "mw_replay_test.bin";
  replay.SaveFile(path);
  ReplayBuffer from_file(12, 3, 2, 3);
  from_file.LoadFile(path);
  EXPECT_EQ(from_file.size(), 5);
  {
    std::ofstream(path, std::ios::binary | std::ios::trunc) << flipped;
  }
  try {
    from_file.LoadFile(path);
    ADD_FAILURE() << "corrupt file loaded";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
  }
  std::filesystem::remove(path);
  EXPECT_THROW(from_file.LoadFile(path), Error);
}

// Nine transitions over tasks 0 and 1 of a (12, 3, 2, 3) buffer: task 0
// wrapped (5 into 4 rows), task 1 full, task 2 empty.
ReplayBuffer FixedBuffer() {
  ReplayBuffer replay(12, 3, 2, 3);
  for (int k = 0; k < 9; ++k) {
    const std::vector<float> obs = {float(k), float(k) + 0.5f, -float(k)};
    const std::vector<float> action = {0.25f * k, -1.0f};
    const std::vector<float> next = {1.0f, 2.0f, float(k)};
    replay.Add(k % 2, obs, action, 0.125f * k, next, k % 3 == 0);
  }
  return replay;
}

// The bytes of a snapshot did not change when its reader and writer moved to
// replay_snapshot.cc (torch-free, so that the fuzz build reads it): the
// checksum below is that of the snapshot the earlier code wrote. (The format
// stores this machine's byte order; this is a little-endian figure.)
TEST(ReplayBufferTest, SnapshotBytesAreThoseOfTheFormat) {
  std::stringstream out;
  FixedBuffer().Save(out);
  const std::string bytes = out.str();
  EXPECT_EQ(bytes.size(), 488u);
  EXPECT_EQ(ReplaySnapshotChecksum(bytes), 0x4c14fb91f53906b7ULL);
}

// A snapshot resealed by hand after an edit (a checksum finds damage, not
// edits): the rows are checked too, and the buffer keeps what it held.
TEST(ReplayBufferTest, AResealedSnapshotWithAForeignTaskIndexIsRefused) {
  std::stringstream out;
  FixedBuffer().Save(out);
  std::string bytes = out.str();
  // header 48 bytes, sizes and ring positions 48, task 0's 4 rows of 10
  // floats 160: its first task index is at 256
  const int64_t foreign = 1;
  std::memcpy(bytes.data() + 256, &foreign, sizeof(foreign));
  const uint64_t sum = ReplaySnapshotChecksum(std::string_view(bytes).substr(0, bytes.size() - 8));
  std::memcpy(bytes.data() + bytes.size() - 8, &sum, sizeof(sum));
  ReplayBuffer target(12, 3, 2, 3);
  AddTransition(target, 2, 5);
  std::stringstream in(bytes);
  try {
    target.Load(in);
    ADD_FAILURE() << "a foreign task index was loaded";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("foreign task index in task 0"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(target.size(), 1);
  EXPECT_EQ(target.size(2), 1);
}

TEST(ReplayBufferTest, RejectsBadArguments) {
  EXPECT_THROW(ReplayBuffer(2, 3, 2, 3), ConfigError);
  EXPECT_THROW(ReplayBuffer(10, 0, 2, 1), ConfigError);
  // 10^9 transitions of 1,000-dim observations (8 TB) are refused before allocating.
  try {
    ReplayBuffer(1000000000, 1000, 4, 1);
    ADD_FAILURE() << "an 8 TB replay buffer was accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("replay.capacity"), std::string::npos) << e.what();
  }
  ReplayBuffer replay(10, 3, 2, 1);
  std::vector<float> obs(3), action(2), bad(4);
  EXPECT_THROW(replay.Add(1, obs, action, 0, obs, false), Error);
  EXPECT_THROW(replay.Add(0, bad, action, 0, obs, false), Error);
  EXPECT_THROW(replay.Add(0, obs, bad, 0, obs, false), Error);
  EXPECT_EQ(ParseReplaySampling("balanced"), ReplaySampling::kBalanced);
  EXPECT_THROW(ParseReplaySampling("weighted"), ConfigError);
}

}  // namespace
}  // namespace manyworlds::agents
