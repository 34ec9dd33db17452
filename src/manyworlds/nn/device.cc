#include "manyworlds/nn/device.h"

#include <torch/cuda.h>

#include "manyworlds/core/error.h"

namespace manyworlds::nn {
namespace {

constexpr int kMaxDeviceIndex = 255;

// A value as an error line shows it: at most 40 characters, and one line.
std::string Shown(const std::string& text) {
  std::string shown =
      text.size() > 40 ? text.substr(0, 32) + "... (" + std::to_string(text.size()) + " characters)"
                       : text;
  for (char& c : shown) {
    if (c == '\n' || c == '\r') c = ' ';
  }
  return shown;
}

[[noreturn]] void Refuse(const std::string& key, const std::string& text, const std::string& why) {
  throw ConfigError("'" + key + "' = '" + Shown(text) + "': " + why);
}

}  // namespace

DeviceRequest ParseDevice(const std::string& text, const std::string& key) {
  if (text == "auto") return {DeviceRequest::Kind::kAuto, -1};
  if (text == "cpu") return {DeviceRequest::Kind::kCpu, -1};
  if (text == "cuda") return {DeviceRequest::Kind::kCuda, -1};
  const std::string prefix = "cuda:";
  if (text.size() > prefix.size() && text.size() <= prefix.size() + 3 &&
      text.compare(0, prefix.size(), prefix) == 0 &&
      text.find_first_not_of("0123456789", prefix.size()) == std::string::npos) {
    const int index = std::stoi(text.substr(prefix.size()));
    if (index <= kMaxDeviceIndex) return {DeviceRequest::Kind::kCuda, index};
  }
  Refuse(key, text,
         std::string("not a device; allowed: ") + kDeviceValues + " (N in [0, " +
             std::to_string(kMaxDeviceIndex) + "])");
}

DeviceFacts QueryDevices() {
  DeviceFacts facts;
  facts.cuda_built = torch::cuda::is_available() || at::hasCUDA();
  facts.gpus = facts.cuda_built ? static_cast<int>(torch::cuda::device_count()) : 0;
  return facts;
}

std::string ResolveDevice(const std::string& text, const std::string& key,
                          const DeviceFacts& facts) {
  const DeviceRequest request = ParseDevice(text, key);
  if (request.kind != DeviceRequest::Kind::kCuda) return "cpu";
  if (!facts.cuda_built) {
    Refuse(key, text,
           "this build's libtorch has no CUDA (Debian's libtorch is CPU-only); build against a "
           "CUDA libtorch (scripts/build_with_torch.sh) or use cpu or auto");
  }
  if (facts.gpus == 0) {
    Refuse(key, text,
           "libtorch has CUDA but sees no GPU (no driver, or CUDA_VISIBLE_DEVICES hides them); "
           "use cpu or auto");
  }
  if (request.index >= facts.gpus) {
    Refuse(key, text,
           "this machine has " + std::to_string(facts.gpus) + " GPU" +
               (facts.gpus == 1 ? "" : "s") + " (cuda:0 to cuda:" + std::to_string(facts.gpus - 1) +
               ")");
  }
  Refuse(key, text,
         "the learners run on the CPU only in this version (auto picks it); GPU learners are "
         "not built yet");
}

std::string ResolveDevice(const std::string& text, const std::string& key) {
  return ResolveDevice(text, key, QueryDevices());
}

}  // namespace manyworlds::nn
