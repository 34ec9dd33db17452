// agent.device: what parses, and the one-line reasons a request for a GPU is refused on a build or
// machine that cannot give one (the learners run on the CPU in this version).
#include "manyworlds/nn/device.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "manyworlds/core/error.h"

namespace manyworlds::nn {
namespace {

// The ConfigError's message, or "" if none was thrown.
template <class F>
std::string ErrorOf(F&& f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(DeviceTest, ParsesTheFourForms) {
  EXPECT_EQ(ParseDevice("auto", "k").kind, DeviceRequest::Kind::kAuto);
  EXPECT_EQ(ParseDevice("cpu", "k").kind, DeviceRequest::Kind::kCpu);
  const DeviceRequest bare = ParseDevice("cuda", "k");
  EXPECT_EQ(bare.kind, DeviceRequest::Kind::kCuda);
  EXPECT_EQ(bare.index, -1);
  const DeviceRequest third = ParseDevice("cuda:3", "k");
  EXPECT_EQ(third.kind, DeviceRequest::Kind::kCuda);
  EXPECT_EQ(third.index, 3);
  EXPECT_EQ(ParseDevice("cuda:255", "k").index, 255);
}

TEST(DeviceTest, AnythingElseIsOneLineNamingTheKeyAndTheAllowedValues) {
  for (const std::string& bad : std::vector<std::string>{
           "", "CPU", "gpu", "cuda:", "cuda:-1", "cuda:256", "cuda:1x", "cuda:0:1", "cuda:0001",
           "mps", " cpu", "cpu\n", std::string(5000, 'x')}) {
    const std::string message = ErrorOf([&] { ParseDevice(bad, "agent.device"); });
    ASSERT_FALSE(message.empty()) << "accepted '" << bad << "'";
    EXPECT_NE(message.find("'agent.device'"), std::string::npos) << message;
    EXPECT_NE(message.find("allowed: auto, cpu, cuda, cuda:N"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_LT(message.size(), 200u) << message;
  }
}

TEST(DeviceTest, CpuAndAutoResolveToTheCpuOnEveryMachine) {
  for (const DeviceFacts facts :
       {DeviceFacts{false, 0}, DeviceFacts{true, 0}, DeviceFacts{true, 2}}) {
    EXPECT_EQ(ResolveDevice("cpu", "k", facts), "cpu");
    EXPECT_EQ(ResolveDevice("auto", "k", facts), "cpu");
  }
}

TEST(DeviceTest, AGpuRequestSaysWhyThisBuildOrMachineCannotGiveOne) {
  struct Case {
    DeviceFacts facts;
    std::string device;
    std::string why;
  };
  const Case cases[] = {
      {{false, 0}, "cuda", "libtorch has no CUDA"},
      {{false, 0}, "cuda:0", "scripts/build_with_torch.sh"},
      {{true, 0}, "cuda", "sees no GPU"},
      {{true, 1}, "cuda:1", "this machine has 1 GPU (cuda:0 to cuda:0)"},
      {{true, 2}, "cuda:7", "this machine has 2 GPUs (cuda:0 to cuda:1)"},
      {{true, 2}, "cuda:1", "run on the CPU only in this version"},
  };
  for (const Case& c : cases) {
    const std::string message = ErrorOf([&] { ResolveDevice(c.device, "agent.device", c.facts); });
    EXPECT_NE(message.find("'agent.device' = '" + c.device + "'"), std::string::npos) << message;
    EXPECT_NE(message.find(c.why), std::string::npos) << c.device << ": " << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

TEST(DeviceTest, ThisBuildAnswersForItself) {
  const DeviceFacts facts = QueryDevices();
  EXPECT_GE(facts.gpus, 0);
  if (!facts.cuda_built) {
    EXPECT_EQ(facts.gpus, 0);
  }
  EXPECT_EQ(ResolveDevice("auto", "agent.device"), "cpu");
  EXPECT_FALSE(ErrorOf([] { ResolveDevice("cuda", "agent.device"); }).empty());
}

}  // namespace
}  // namespace manyworlds::nn
