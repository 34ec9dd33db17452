// FrameStack: the env observation becomes the last `frames` inner env observations,
// concatenated along the first axis, oldest first (a Box of shape (k * d0, d1, ...): for
// channels-first pixels (3, 84, 84) and k = 3, MTEnv's (9, 84, 84)). At reset every slot holds
// the first observation, as MTEnv's and dmc2gym's FrameStack do. Box observations only.
#ifndef MANYWORLDS_CORE_WRAPPERS_FRAME_STACK_H_
#define MANYWORLDS_CORE_WRAPPERS_FRAME_STACK_H_

#include <cstdint>
#include <memory>
#include <vector>

#include "manyworlds/core/wrapper.h"

namespace manyworlds {

class FrameStack : public Wrapper {
 public:
  static constexpr int64_t kMaxFrames = 64;

  // Throws ConfigError for frames outside [1, kMaxFrames] or a non-Box env observation.
  FrameStack(std::unique_ptr<Env> inner, int64_t frames);

  int64_t frames() const { return frames_; }

 protected:
  void DoReset(const ObsView& out) override;
  void DoStep(std::span<const float> action, const StepView& out) override;

 private:
  // Writes the stack, oldest first, into `out` (newest_ is the slot of the latest frame).
  void WriteStack(std::span<float> out) const;

  int64_t frames_;
  int64_t frame_size_;
  std::vector<float> ring_;  // frames_ x frame_size_
  int64_t newest_ = 0;
};

}  // namespace manyworlds

#endif  // MANYWORLDS_CORE_WRAPPERS_FRAME_STACK_H_
