#include "manyworlds/core/wrappers/frame_stack.h"

#include <algorithm>
#include <string>

#include "manyworlds/core/error.h"

namespace manyworlds {
namespace {

std::unique_ptr<Env> CheckFrames(std::unique_ptr<Env> inner, int64_t frames) {
  if (frames < 1 || frames > FrameStack::kMaxFrames) {
    throw ConfigError("wrapper frame-stack: frames must be in [1, " +
                      std::to_string(FrameStack::kMaxFrames) + "], got " + std::to_string(frames));
  }
  if (inner && !inner->spec().env_obs_space.is_box()) {
    throw ConfigError("wrapper frame-stack on env '" + inner->spec().id +
                      "': needs a Box env observation, got " +
                      inner->spec().env_obs_space.ToString());
  }
  return inner;
}

}  // namespace

FrameStack::FrameStack(std::unique_ptr<Env> inner, int64_t frames)
    : Wrapper(CheckFrames(std::move(inner), frames), "frame-stack"), frames_(frames) {
  const Space& obs = this->inner().spec().env_obs_space;
  frame_size_ = obs.flat_size();
  ring_.assign(static_cast<size_t>(frames_ * frame_size_), 0.0f);
  std::vector<float> low, high;
  for (int64_t k = 0; k < frames_; ++k) {
    low.insert(low.end(), obs.low().begin(), obs.low().end());
    high.insert(high.end(), obs.high().begin(), obs.high().end());
  }
  std::vector<int64_t> shape = obs.shape();
  if (shape.empty()) shape = {1};
  shape[0] *= frames_;
  mutable_spec().env_obs_space = Space::Box(std::move(low), std::move(high), std::move(shape));
}

void FrameStack::WriteStack(std::span<float> out) const {
  for (int64_t k = 0; k < frames_; ++k) {  // oldest (newest_ + 1) first
    const int64_t slot = (newest_ + 1 + k) % frames_;
    std::copy_n(ring_.begin() + slot * frame_size_, frame_size_, out.begin() + k * frame_size_);
  }
}

void FrameStack::DoReset(const ObsView& out) {
  Wrapper::DoReset(ObsView{out.env_obs.first(frame_size_), out.task_obs});
  for (int64_t k = 0; k < frames_; ++k) {
    std::copy_n(out.env_obs.begin(), frame_size_, ring_.begin() + k * frame_size_);
  }
  newest_ = frames_ - 1;
  WriteStack(out.env_obs);
}

void FrameStack::DoStep(std::span<const float> action, const StepView& out) {
  StepView inner_out = out;
  inner_out.env_obs = out.env_obs.first(frame_size_);
  Wrapper::DoStep(action, inner_out);
  newest_ = (newest_ + 1) % frames_;
  std::copy_n(out.env_obs.begin(), frame_size_, ring_.begin() + newest_ * frame_size_);
  WriteStack(out.env_obs);
}

}  // namespace manyworlds
