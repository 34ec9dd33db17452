#include "manyworlds/core/space.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "manyworlds/core/error.h"

namespace manyworlds {
namespace {

int64_t ElementCount(const std::vector<int64_t>& shape) {
  int64_t count = 1;
  for (int64_t d : shape) {
    if (d < 0) throw ConfigError("space shape has a negative dimension");
    count *= d;
  }
  return count;
}

std::string FormatFloat(float x) {
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  std::ostringstream out;
  out << x;
  std::string s = out.str();
  if (s.find_first_of(".e") == std::string::npos) s += ".0";
  return s;
}

std::string FormatShape(const std::vector<int64_t>& shape) {
  std::string s = "(";
  for (size_t i = 0; i < shape.size(); ++i) {
    s += std::to_string(shape[i]);
    if (shape.size() == 1 || i + 1 < shape.size()) s += ",";
    if (i + 1 < shape.size()) s += " ";
  }
  return s + ")";
}

nlohmann::json BoundToJson(float x) {
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  return x;
}

}  // namespace

Space Space::Box(float low, float high, std::vector<int64_t> shape) {
  const int64_t count = ElementCount(shape);
  return Box(std::vector<float>(count, low), std::vector<float>(count, high), std::move(shape));
}

Space Space::Box(std::vector<float> low, std::vector<float> high, std::vector<int64_t> shape) {
  Space space;
  space.kind_ = Kind::kBox;
  space.flat_size_ = ElementCount(shape);
  if (static_cast<int64_t>(low.size()) != space.flat_size_ ||
      static_cast<int64_t>(high.size()) != space.flat_size_) {
    throw ConfigError("Box bounds have " + std::to_string(low.size()) + "/" +
                      std::to_string(high.size()) + " elements but shape " + FormatShape(shape) +
                      " has " + std::to_string(space.flat_size_));
  }
  for (int64_t i = 0; i < space.flat_size_; ++i) {
    if (std::isnan(low[i]) || std::isnan(high[i]) || low[i] > high[i]) {
      throw ConfigError("Box bounds at element " + std::to_string(i) + " are invalid: low " +
                        FormatFloat(low[i]) + ", high " + FormatFloat(high[i]));
    }
  }
  space.shape_ = std::move(shape);
  space.low_ = std::move(low);
  space.high_ = std::move(high);
  return space;
}

Space Space::Discrete(int64_t n) {
  if (n <= 0) throw ConfigError("Discrete(n) needs n >= 1, got " + std::to_string(n));
  Space space;
  space.kind_ = Kind::kDiscrete;
  space.n_ = n;
  space.flat_size_ = 1;
  space.shape_ = {};
  space.low_.clear();
  space.high_.clear();
  return space;
}

bool Space::Contains(std::span<const float> value) const {
  if (static_cast<int64_t>(value.size()) != flat_size_) return false;
  if (kind_ == Kind::kDiscrete) {
    const float v = value[0];
    return std::isfinite(v) && v == std::floor(v) && v >= 0 && v < static_cast<float>(n_);
  }
  for (int64_t i = 0; i < flat_size_; ++i) {
    const float v = value[i];
    if (std::isnan(v) || v < low_[i] || v > high_[i]) return false;
  }
  return true;
}

void Space::Sample(Rng& rng, std::span<float> out) const {
  if (static_cast<int64_t>(out.size()) != flat_size_) {
    throw InvalidActionError("Space::Sample output has " + std::to_string(out.size()) +
                             " elements, expected " + std::to_string(flat_size_));
  }
  if (kind_ == Kind::kDiscrete) {
    out[0] = static_cast<float>(rng.UniformInt(static_cast<uint64_t>(n_)));
    return;
  }
  for (int64_t i = 0; i < flat_size_; ++i) {
    const bool low_finite = std::isfinite(low_[i]);
    const bool high_finite = std::isfinite(high_[i]);
    double v;
    if (low_finite && high_finite) {
      v = rng.Uniform(low_[i], high_[i]);
    } else if (low_finite) {
      v = low_[i] + std::abs(rng.Normal());
    } else if (high_finite) {
      v = high_[i] - std::abs(rng.Normal());
    } else {
      v = rng.Normal();
    }
    // Rounding to float can land exactly on an open upper bound; stay inside.
    out[i] = std::clamp(static_cast<float>(v), low_[i], high_[i]);
  }
}

std::vector<float> Space::Sample(Rng& rng) const {
  std::vector<float> out(flat_size_);
  Sample(rng, out);
  return out;
}

void Space::Clip(std::span<float> value) const {
  if (kind_ != Kind::kBox) return;
  const int64_t count = std::min<int64_t>(flat_size_, value.size());
  for (int64_t i = 0; i < count; ++i) value[i] = std::clamp(value[i], low_[i], high_[i]);
}

std::string Space::ToString() const {
  if (kind_ == Kind::kDiscrete) return "Discrete(" + std::to_string(n_) + ")";
  std::string low_s = "0.0", high_s = "0.0";
  if (flat_size_ > 0) {
    const auto [lo_min, lo_max] = std::minmax_element(low_.begin(), low_.end());
    const auto [hi_min, hi_max] = std::minmax_element(high_.begin(), high_.end());
    low_s = *lo_min == *lo_max ? FormatFloat(*lo_min)
                               : "[" + FormatFloat(*lo_min) + ".." + FormatFloat(*lo_max) + "]";
    high_s = *hi_min == *hi_max ? FormatFloat(*hi_min)
                                : "[" + FormatFloat(*hi_min) + ".." + FormatFloat(*hi_max) + "]";
  }
  return "Box(" + low_s + ", " + high_s + ", " + FormatShape(shape_) + ", float32)";
}

nlohmann::json Space::ToJson() const {
  if (kind_ == Kind::kDiscrete) return {{"type", "Discrete"}, {"n", n_}};
  nlohmann::json low = nlohmann::json::array(), high = nlohmann::json::array();
  for (int64_t i = 0; i < flat_size_; ++i) {
    low.push_back(BoundToJson(low_[i]));
    high.push_back(BoundToJson(high_[i]));
  }
  return {{"type", "Box"}, {"shape", shape_}, {"low", low}, {"high", high}, {"dtype", "float32"}};
}

bool Space::operator==(const Space& other) const {
  return kind_ == other.kind_ && shape_ == other.shape_ && low_ == other.low_ &&
         high_ == other.high_ && n_ == other.n_;
}

}  // namespace manyworlds
