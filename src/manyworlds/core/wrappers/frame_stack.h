// FrameStack: the observation becomes the last `frames` inner observations, concatenated along
// the first axis, oldest first (a Box of shape (k * d0, d1, ...)). At reset every slot holds the
// first observation, as MTEnv's and dmc2gym's FrameStack do.
//
// What is stacked: the pixel observation where the inner env has one (channels-first frames
// (3, 84, 84) and k = 3 give MTEnv's (9, 84, 84); env_obs, the proprioceptive state, stays the
// current one, as an asymmetric critic wants it), else env_obs (a Box).
#ifndef MANYWORLDS_CORE_WRAPPERS_FRAME_STACK_H_
#define MANYWORLDS_CORE_WRAPPERS_FRAME_STACK_H_

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "manyworlds/core/wrapper.h"

namespace manyworlds {

class FrameStack : public Wrapper {
 public:
  static constexpr int64_t kMaxFrames = 64;

  // Throws ConfigError for frames outside [1, kMaxFrames] or an env with neither pixels nor a
  // Box env observation.
  FrameStack(std::unique_ptr<Env> inner, int64_t frames);

  int64_t frames() const { return frames_; }
  bool stacks_pixels() const { return stacks_pixels_; }

 protected:
  void DoReset(const ObsView& out) override;
  void DoStep(std::span<const float> action, const StepView& out) override;

 private:
  // A ring of the last frames of one observation channel (float env_obs or byte pixels).
  template <typename T>
  struct Ring {
    int64_t frames = 0, frame_size = 0;
    std::vector<T> slots;  // frames x frame_size
    int64_t newest = 0;

    void Fill(std::span<const T> first);  // every slot: the first frame
    void Push(std::span<const T> frame);
    void Write(std::span<T> out) const;   // oldest first
  };

  int64_t frames_;
  bool stacks_pixels_;
  Ring<float> obs_ring_;
  Ring<uint8_t> pixel_ring_;
};

}  // namespace manyworlds

#endif  // MANYWORLDS_CORE_WRAPPERS_FRAME_STACK_H_
