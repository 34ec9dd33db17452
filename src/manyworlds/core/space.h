// Action and observation spaces: Box (float32 bounds and shape) and Discrete.
//
// Every value crosses the API as a flat float array. A Box of shape (3, 2) is
// 6 floats in row-major order; a Discrete(n) value is one float holding an
// integer in [0, n).
#ifndef MANYWORLDS_CORE_SPACE_H_
#define MANYWORLDS_CORE_SPACE_H_

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "manyworlds/core/rng.h"

namespace manyworlds {

class Space {
 public:
  enum class Kind { kBox, kDiscrete };

  // A Box with the same bounds on every element. Bounds may be infinite.
  static Space Box(float low, float high, std::vector<int64_t> shape);
  // A Box with per-element bounds; low and high have the shape's element count.
  static Space Box(std::vector<float> low, std::vector<float> high, std::vector<int64_t> shape);
  static Space Discrete(int64_t n);

  // An empty Box of shape (0,).
  Space() : shape_{0} {}

  Kind kind() const { return kind_; }
  bool is_box() const { return kind_ == Kind::kBox; }
  bool is_discrete() const { return kind_ == Kind::kDiscrete; }

  // Number of floats a value of this space occupies (1 for Discrete).
  int64_t flat_size() const { return flat_size_; }
  const std::vector<int64_t>& shape() const { return shape_; }
  // Box only: per-element bounds (flat_size() each).
  const std::vector<float>& low() const { return low_; }
  const std::vector<float>& high() const { return high_; }
  // Discrete only.
  int64_t n() const { return n_; }

  // True if value has flat_size() finite elements inside the bounds
  // (Discrete: an integer in [0, n)).
  bool Contains(std::span<const float> value) const;
  // Writes a uniformly random element into out (flat_size() floats). Boxes
  // with an infinite bound on an element sample that element from a
  // standard normal (shifted into the half-bounded range), as Gymnasium does.
  void Sample(Rng& rng, std::span<float> out) const;
  std::vector<float> Sample(Rng& rng) const;
  // Clips a Box value into the bounds, in place. No-op for Discrete.
  void Clip(std::span<float> value) const;

  // "Box(-1.0, 1.0, (4,), float32)" or "Discrete(3)". Per-element bounds are
  // summarised by their range.
  std::string ToString() const;
  nlohmann::json ToJson() const;

  bool operator==(const Space& other) const;

 private:
  Kind kind_ = Kind::kBox;
  std::vector<int64_t> shape_;
  std::vector<float> low_, high_;
  int64_t n_ = 0;
  int64_t flat_size_ = 0;
};

}  // namespace manyworlds

#endif  // MANYWORLDS_CORE_SPACE_H_
