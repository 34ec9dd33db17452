// Where the learners run: the `agent.device` setting (auto | cpu | cuda | cuda:N).
//
// The learners run on the CPU in this version; a build against a CUDA libtorch
// (scripts/build_with_torch.sh) is the first step towards them running on a GPU.
// Until they do, asking for a GPU is a one-line ConfigError that says why this
// machine or build cannot give one, before anything is allocated, and `auto`
// picks the CPU.
#ifndef MANYWORLDS_NN_DEVICE_H_
#define MANYWORLDS_NN_DEVICE_H_

#include <string>

namespace manyworlds::nn {

struct DeviceRequest {
  enum class Kind { kAuto, kCpu, kCuda };
  Kind kind = Kind::kAuto;
  int index = -1;  // cuda:N; -1 for a bare "cuda" (the current GPU)
};

// The values `key` may take, for help texts and errors.
inline constexpr const char* kDeviceValues = "auto, cpu, cuda, cuda:N";

// "auto", "cpu", "cuda" or "cuda:N" (N in [0, 255]); anything else is a ConfigError naming `key`
// and the allowed values.
DeviceRequest ParseDevice(const std::string& text, const std::string& key);

// What this build and machine offer, for errors and `bench agent --json`.
struct DeviceFacts {
  bool cuda_built = false;  // libtorch was built with CUDA
  int gpus = 0;             // GPUs libtorch sees (0 without CUDA)
};
DeviceFacts QueryDevices();

// The device the learners use for `text`: "cpu". A request for a GPU is a one-line
// ConfigError naming `key` and the reason: a libtorch without CUDA, no GPU seen, an index past
// the GPUs there are, or (with a GPU there) learners that do not run on one yet. `facts` is
// what QueryDevices() returns (a parameter, so that tests can pose other machines).
std::string ResolveDevice(const std::string& text, const std::string& key,
                          const DeviceFacts& facts);
std::string ResolveDevice(const std::string& text, const std::string& key);

}  // namespace manyworlds::nn

#endif  // MANYWORLDS_NN_DEVICE_H_
