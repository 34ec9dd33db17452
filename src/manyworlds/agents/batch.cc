#include "manyworlds/agents/batch.h"

#include <string>
#include <vector>

#include "manyworlds/core/error.h"

namespace manyworlds::agents {
namespace {

std::string Shape(const torch::Tensor& t) {
  if (!t.defined()) return "undefined";
  std::string s = "(";
  for (int64_t i = 0; i < t.dim(); ++i) s += (i ? ", " : "") + std::to_string(t.size(i));
  return s + ")";
}

void Check(const torch::Tensor& t, const char* name, std::vector<int64_t> shape,
           std::vector<torch::ScalarType> dtypes) {
  bool ok = t.defined() && t.device().is_cpu() && t.sizes() == torch::IntArrayRef(shape);
  bool dtype_ok = false;
  for (torch::ScalarType d : dtypes) dtype_ok = dtype_ok || (t.defined() && t.scalar_type() == d);
  if (ok && dtype_ok) return;
  std::string want = "(";
  for (size_t i = 0; i < shape.size(); ++i) want += (i ? ", " : "") + std::to_string(shape[i]);
  throw Error(std::string("Batch.") + name + ": expected a CPU tensor of shape " + want +
              ") and type " + std::string(c10::toString(dtypes[0])) + ", got " + Shape(t) +
              (t.defined() ? std::string(" ") + c10::toString(t.scalar_type()) : ""));
}

}  // namespace

void ValidateBatch(const Batch& batch, int64_t obs_dim, int64_t action_dim, int64_t num_tasks,
                   int64_t pixel_size) {
  const int64_t b = batch.size();
  if (b <= 0) throw Error("Batch: empty or missing obs");
  Check(batch.obs, "obs", {b, obs_dim}, {torch::kFloat32});
  Check(batch.action, "action", {b, action_dim}, {torch::kFloat32});
  Check(batch.reward, "reward", {b}, {torch::kFloat32});
  Check(batch.next_obs, "next_obs", {b, obs_dim}, {torch::kFloat32});
  Check(batch.done, "done", {b}, {torch::kFloat32, torch::kBool});
  Check(batch.task_index, "task_index", {b}, {torch::kInt64});
  if (pixel_size > 0) {
    Check(batch.pixels, "pixels", {b, pixel_size}, {torch::kUInt8});
    Check(batch.next_pixels, "next_pixels", {b, pixel_size}, {torch::kUInt8});
  }
  auto [lo, hi] = torch::aminmax(batch.task_index);
  if (lo.item<int64_t>() < 0 || hi.item<int64_t>() >= num_tasks) {
    throw Error("Batch.task_index: values must lie in [0, " + std::to_string(num_tasks) +
                "), got [" + std::to_string(lo.item<int64_t>()) + ", " +
                std::to_string(hi.item<int64_t>()) + "]");
  }
}

}  // namespace manyworlds::agents
