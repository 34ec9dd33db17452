// A batch of transitions for off-policy learners, as CPU tensors.
#ifndef MANYWORLDS_AGENTS_BATCH_H_
#define MANYWORLDS_AGENTS_BATCH_H_

#include <cstdint>

#include <torch/torch.h>

namespace manyworlds::agents {

struct Batch {
  // (B, obs_dim) float32: the env observation, never a task id (learners
  // condition on task_index themselves).
  torch::Tensor obs;
  torch::Tensor action;      // (B, action_dim) float32, in the policy's (-1, 1) range
  torch::Tensor reward;      // (B) float32
  torch::Tensor next_obs;    // (B, obs_dim) float32
  // (B) float32 (or bool): 1 where the MDP terminated. A time-limit
  // truncation is not done: the target still bootstraps from next_obs.
  torch::Tensor done;
  torch::Tensor task_index;  // (B) int64 in [0, num_tasks)
  // Pixel observations of obs and next_obs (obs=pixels envs): (B, pixel_size)
  // uint8, the frames flattened channels first; undefined without pixels.
  torch::Tensor pixels;
  torch::Tensor next_pixels;

  int64_t size() const { return obs.defined() ? obs.size(0) : 0; }
};

// Throws Error naming the field whose shape or dtype is wrong. Task indices
// are range-checked (one reduction over B values). pixel_size > 0: pixels
// and next_pixels must be (B, pixel_size) uint8.
void ValidateBatch(const Batch& batch, int64_t obs_dim, int64_t action_dim, int64_t num_tasks,
                   int64_t pixel_size = 0);

}  // namespace manyworlds::agents

#endif  // MANYWORLDS_AGENTS_BATCH_H_
