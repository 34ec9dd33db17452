#include "manyworlds/nn/worker_pool.h"

#include <atomic>
#include <stdexcept>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <torch/torch.h>

#include "manyworlds/core/error.h"
#include "manyworlds/nn/mlp.h"

namespace manyworlds::nn {
namespace {

TEST(WorkerPoolTest, RunsEveryPartOnceOnSeveralThreads) {
  WorkerPool pool(3);
  EXPECT_EQ(pool.num_threads(), 3);
  for (int round = 0; round < 50; ++round) {
    std::vector<std::atomic<int>> calls(7);
    pool.Run(7, [&](int part) { calls[static_cast<size_t>(part)]++; });
    for (const std::atomic<int>& c : calls) ASSERT_EQ(c.load(), 1) << "round " << round;
  }
  pool.Run(0, [](int) { FAIL() << "no part to run"; });
}

TEST(WorkerPoolTest, UsesMoreThanTheCallingThread) {
  WorkerPool pool(2);
  std::vector<std::thread::id> ids(2);
  std::atomic<int> arrived{0};
  // Each part waits for the other: only two threads at once can finish.
  pool.Run(2, [&](int part) {
    ids[static_cast<size_t>(part)] = std::this_thread::get_id();
    arrived++;
    while (arrived.load() < 2) std::this_thread::yield();
  });
  EXPECT_NE(ids[0], ids[1]);
}

TEST(WorkerPoolTest, RethrowsAPartsExceptionAfterAllParts) {
  WorkerPool pool(2);
  std::atomic<int> finished{0};
  EXPECT_THROW(pool.Run(4,
                        [&](int part) {
                          if (part == 1) throw std::runtime_error("part 1 failed");
                          finished++;
                        }),
               std::runtime_error);
  EXPECT_EQ(finished.load(), 3);
  // The pool stays usable.
  pool.Run(2, [&](int) { finished++; });
  EXPECT_EQ(finished.load(), 5);
  EXPECT_THROW(WorkerPool(0), ConfigError);
}

TEST(WorkerPoolTest, WorkersKeepOneIntraOpThread) {
  torch::set_num_threads(1);
  WorkerPool pool(2);
  std::vector<int> threads(2, -1);
  std::atomic<int> arrived{0};
  pool.Run(2, [&](int part) {
    threads[static_cast<size_t>(part)] = torch::get_num_threads();
    arrived++;
    while (arrived.load() < 2) std::this_thread::yield();
  });
  EXPECT_EQ(threads[0], 1);
  EXPECT_EQ(threads[1], 1);
}

TEST(GradientReplicaTest, ConcurrentBackwardsAddUpToTheFullBatchGradient) {
  MlpOptions o;
  o.input_dim = 5;
  o.output_dim = 2;
  o.hidden_dim = 8;
  o.num_layers = 2;
  Mlp net(o, at::detail::createCPUGenerator(3));
  GradientReplica replica = net->MakeGradientReplica();
  ASSERT_EQ(replica.params.size(), net->params().size());
  EXPECT_EQ(replica.flat_grad.numel(), net->num_params());
  // The replica computes with the module's values (shared storage).
  const torch::Tensor x = torch::randn({6, 5}, at::detail::createCPUGenerator(4));
  EXPECT_TRUE(torch::equal(net->Forward(x), net->Forward(x, replica.params)));

  // Whole batch, the usual way.
  net->ZeroGrad();
  net->Forward(x).square().sum().backward();
  const torch::Tensor full = net->flat_grad().clone();

  // Two halves at once on two threads, one into the module, one into the replica.
  WorkerPool pool(2);
  net->ZeroGrad();
  replica.ZeroGrad();
  pool.Run(2, [&](int part) {
    const torch::Tensor half = x.narrow(0, 3 * part, 3);
    const at::ArrayRef<torch::Tensor> params =
        part == 0 ? at::ArrayRef<torch::Tensor>(net->params()) : replica.params;
    net->Forward(half, params).square().sum().backward();
  });
  EXPECT_GT(replica.flat_grad.abs().sum().item<float>(), 0.0f);
  EXPECT_TRUE(torch::allclose(net->flat_grad() + replica.flat_grad, full, 1e-5, 1e-6));
  replica.ZeroGrad();
  EXPECT_EQ(replica.flat_grad.abs().sum().item<float>(), 0.0f);
}

}  // namespace
}  // namespace manyworlds::nn
