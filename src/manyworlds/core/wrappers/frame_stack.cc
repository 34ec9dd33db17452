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
  if (inner && inner->spec().pixel_space.flat_size() == 0 && !inner->spec().env_obs_space.is_box()) {
    throw ConfigError("wrapper frame-stack on env '" + inner->spec().id +
                      "': needs pixels or a Box env observation, got " +
                      inner->spec().env_obs_space.ToString());
  }
  return inner;
}

// The space of `frames` stacked values of `space` (a Box): bounds repeated, first axis scaled.
Space Stacked(const Space& space, int64_t frames) {
  std::vector<float> low, high;
  for (int64_t k = 0; k < frames; ++k) {
    low.insert(low.end(), space.low().begin(), space.low().end());
    high.insert(high.end(), space.high().begin(), space.high().end());
  }
  std::vector<int64_t> shape = space.shape();
  if (shape.empty()) shape = {1};
  shape[0] *= frames;
  return Space::Box(std::move(low), std::move(high), std::move(shape));
}

}  // namespace

template <typename T>
void FrameStack::Ring<T>::Fill(std::span<const T> first) {
  for (int64_t k = 0; k < frames; ++k) std::copy_n(first.begin(), frame_size, slots.begin() + k * frame_size);
  newest = frames - 1;
}

template <typename T>
void FrameStack::Ring<T>::Push(std::span<const T> frame) {
  newest = (newest + 1) % frames;
  std::copy_n(frame.begin(), frame_size, slots.begin() + newest * frame_size);
}

template <typename T>
void FrameStack::Ring<T>::Write(std::span<T> out) const {
  for (int64_t k = 0; k < frames; ++k) {  // oldest (newest + 1) first
    const int64_t slot = (newest + 1 + k) % frames;
    std::copy_n(slots.begin() + slot * frame_size, frame_size, out.begin() + k * frame_size);
  }
}

FrameStack::FrameStack(std::unique_ptr<Env> inner, int64_t frames)
    : Wrapper(CheckFrames(std::move(inner), frames), "frame-stack"), frames_(frames) {
  const EnvSpec& inner_spec = this->inner().spec();
  stacks_pixels_ = inner_spec.pixel_space.flat_size() > 0;
  if (stacks_pixels_) {
    pixel_ring_ = {frames_, inner_spec.pixel_space.flat_size(),
                   std::vector<uint8_t>(frames_ * inner_spec.pixel_space.flat_size()), 0};
    mutable_spec().pixel_space = Stacked(inner_spec.pixel_space, frames_);
  } else {
    obs_ring_ = {frames_, inner_spec.env_obs_space.flat_size(),
                 std::vector<float>(frames_ * inner_spec.env_obs_space.flat_size()), 0};
    mutable_spec().env_obs_space = Stacked(inner_spec.env_obs_space, frames_);
  }
}

void FrameStack::DoReset(const ObsView& out) {
  if (stacks_pixels_) {
    const std::span<uint8_t> frame = out.pixels.first(pixel_ring_.frame_size);
    Wrapper::DoReset(ObsView{out.env_obs, out.task_obs, frame});
    pixel_ring_.Fill(frame);
    pixel_ring_.Write(out.pixels);
  } else {
    const std::span<float> frame = out.env_obs.first(obs_ring_.frame_size);
    Wrapper::DoReset(ObsView{frame, out.task_obs, out.pixels});
    obs_ring_.Fill(frame);
    obs_ring_.Write(out.env_obs);
  }
}

void FrameStack::DoStep(std::span<const float> action, const StepView& out) {
  StepView inner_out = out;
  if (stacks_pixels_) {
    inner_out.pixels = out.pixels.first(pixel_ring_.frame_size);
    Wrapper::DoStep(action, inner_out);
    pixel_ring_.Push(inner_out.pixels);
    pixel_ring_.Write(out.pixels);
  } else {
    inner_out.env_obs = out.env_obs.first(obs_ring_.frame_size);
    Wrapper::DoStep(action, inner_out);
    obs_ring_.Push(inner_out.env_obs);
    obs_ring_.Write(out.env_obs);
  }
}

}  // namespace manyworlds
