#include "manyworlds/boxworld/world.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <set>

#include "manyworlds/core/error.h"

namespace manyworlds::boxworld {
namespace {

constexpr double kPi = std::numbers::pi;

std::string Num(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.6g", value);
  return text;
}

[[noreturn]] void Fail(const std::string& message) {
  throw ConfigError("box world: " + message);
}

// value in [low, high] (NaN fails); `why` explains a derived bound.
void CheckRange(const std::string& name, double value, double low, double high,
                const std::string& why = "") {
  if (value >= low && value <= high) return;
  Fail(name + " must be in [" + Num(low) + ", " + Num(high) + "]" +
       (why.empty() ? "" : " (" + why + ")") + ", got " + Num(value));
}

// value in (0, high]
void CheckPositive(const std::string& name, double value, double high) {
  if (value > 0 && value <= high) return;
  Fail(name + " must be in (0, " + Num(high) + "], got " + Num(value));
}

// Footprint side (with clearance) used by the fill rule.
double FillSide(double radius) { return 2.0 * (radius + kPlacementClearance); }

double AgentFill(const WorldParams& w) {
  const double side = FillSide(w.agent_radius);
  return side * side;
}

// How many boxes of footprint radius `radius` fit next to the agent.
int MaxBoxesThatFit(double floor_size, double agent_fill, double radius) {
  const double free = kMaxFill * floor_size * floor_size - agent_fill;
  const double side = FillSide(radius);
  if (free <= 0) return 0;
  return std::min(kMaxBoxesLimit, static_cast<int>(std::floor(free / (side * side))));
}

double MaxTargetDistance(double floor_size, double success_radius) {
  return (floor_size - 2.0 * success_radius) / std::numbers::sqrt2;
}

double Distance(const Vec2& a, const Vec2& b) { return std::hypot(a[0] - b[0], a[1] - b[1]); }


Rgba ShapeColor(Shape shape) {
  switch (shape) {
    case Shape::kBox: return {0.55, 0.55, 0.6, 1.0};
    case Shape::kCylinder: return {0.85, 0.6, 0.2, 1.0};
    case Shape::kSphere: return {0.3, 0.7, 0.4, 1.0};
  }
  return {0.55, 0.55, 0.6, 1.0};
}

constexpr Rgba kPalette[] = {
    {0.90, 0.60, 0.00, 1}, {0.35, 0.70, 0.90, 1}, {0.00, 0.60, 0.50, 1},
    {0.95, 0.90, 0.25, 1}, {0.00, 0.45, 0.70, 1}, {0.80, 0.40, 0.00, 1},
    {0.80, 0.60, 0.70, 1}, {0.55, 0.55, 0.60, 1}};

// --- JSON reading -----------------------------------------------------------

class JsonObject {
 public:
  JsonObject(const nlohmann::json& json, std::string path) : json_(json), path_(std::move(path)) {
    if (!json_.is_object()) Fail(Name("") + "must be a JSON object, got " + json_.dump());
  }

  void ExpectKeys(std::initializer_list<std::string_view> keys) const {
    for (const auto& [key, value] : json_.items()) {
      if (std::find(keys.begin(), keys.end(), key) == keys.end()) {
        std::string allowed;
        for (const auto k : keys) allowed += (allowed.empty() ? "" : ", ") + std::string(k);
        Fail(Name(key) + "is not a world parameter (allowed: " + allowed + ")");
      }
    }
  }
  double Number(std::string_view key) const {
    const nlohmann::json& v = Field(key);
    if (!v.is_number()) Fail(Name(key) + "must be a number, got " + v.dump());
    return v.get<double>();
  }
  std::string String(std::string_view key) const {
    const nlohmann::json& v = Field(key);
    if (!v.is_string()) Fail(Name(key) + "must be a string, got " + v.dump());
    return v.get<std::string>();
  }
  template <size_t N>
  std::array<double, N> Numbers(std::string_view key) const {
    const nlohmann::json& v = Field(key);
    if (!v.is_array() || v.size() != N) {
      Fail(Name(key) + "must be an array of " + std::to_string(N) + " numbers, got " + v.dump());
    }
    std::array<double, N> out{};
    for (size_t i = 0; i < N; ++i) {
      if (!v[i].is_number()) {
        Fail(Name(key).substr(0, Name(key).size() - 1) + "[" + std::to_string(i) +
             "] must be a number, got " + v[i].dump());
      }
      out[i] = v[i].get<double>();
    }
    return out;
  }
  const nlohmann::json& Field(std::string_view key) const {
    auto it = json_.find(std::string(key));
    if (it == json_.end()) Fail(Name(key) + "is missing");
    return *it;
  }
  // "boxes[1].size " (with the space the message continues after)
  std::string Name(std::string_view key) const {
    if (key.empty()) return path_.empty() ? "the world " : path_ + " ";
    return (path_.empty() ? "" : path_ + ".") + std::string(key) + " ";
  }

 private:
  const nlohmann::json& json_;
  std::string path_;
};

std::string BoxName(size_t i) { return "boxes[" + std::to_string(i) + "]"; }

}  // namespace

const char* ShapeName(Shape shape) {
  switch (shape) {
    case Shape::kBox: return "box";
    case Shape::kCylinder: return "cylinder";
    case Shape::kSphere: return "sphere";
  }
  return "box";
}

std::optional<Shape> ParseShape(std::string_view name) {
  for (const Shape s : {Shape::kBox, Shape::kCylinder, Shape::kSphere}) {
    if (name == ShapeName(s)) return s;
  }
  return std::nullopt;
}

double FootprintRadius(const BoxParams& box) {
  return box.shape == Shape::kBox ? box.size * std::numbers::sqrt2 : box.size;
}

void ValidateObjects(const WorldParams& w) {
  CheckRange("floor_size", w.floor_size, kMinFloorSize, kMaxFloorSize);
  const double quarter = w.floor_size / 4;
  CheckRange("wall_height", w.wall_height, kMinWallHeight, kMaxWallHeight);
  CheckRange("agent_radius", w.agent_radius, kMinObjectSize, quarter, "up to floor_size / 4");
  CheckPositive("agent_force", w.agent_force, kMaxAgentForce);
  CheckPositive("agent_torque", w.agent_torque, kMaxAgentTorque);
  CheckRange("success_radius", w.success_radius, kMinObjectSize, quarter, "up to floor_size / 4");
  CheckRange("min_target_distance", w.min_target_distance, w.success_radius,
             MaxTargetDistance(w.floor_size, w.success_radius),
             "success_radius to (floor_size - 2 success_radius) / sqrt(2); a larger floor "
             "allows more");
  const int n = static_cast<int>(w.boxes.size());
  if (n > kMaxBoxesLimit) {
    Fail("num_boxes must be in [0, " + std::to_string(kMaxBoxesLimit) + "], got " +
         std::to_string(n));
  }
  double fill = AgentFill(w);
  double largest = 0;
  for (size_t i = 0; i < w.boxes.size(); ++i) {
    const BoxParams& b = w.boxes[i];
    const std::string name = BoxName(i);
    CheckRange(name + ".size", b.size, kMinObjectSize, quarter, "up to floor_size / 4");
    CheckRange(name + ".mass", b.mass, kMinMass, kMaxMass);
    CheckRange(name + ".friction", b.friction, 0.0, kMaxFriction);
    for (size_t k = 0; k < 4; ++k) {
      CheckRange(name + ".rgba[" + std::to_string(k) + "]", b.rgba[k], 0.0, 1.0);
    }
    CheckRange(name + ".start_yaw", b.start_yaw, -kPi, kPi);
    const double side = FillSide(FootprintRadius(b));
    fill += side * side;
    largest = std::max(largest, FootprintRadius(b));
  }
  if (fill > kMaxFill * w.floor_size * w.floor_size) {
    Fail("num_boxes must be in [0, " +
         std::to_string(MaxBoxesThatFit(w.floor_size, AgentFill(w), largest)) + "] on a " +
         Num(w.floor_size) + " m floor with boxes of footprint radius up to " + Num(largest) +
         " m (their footprints may cover at most " + Num(100 * kMaxFill) +
         "% of the floor), got " + std::to_string(n));
  }
  CheckRange("agent_start_yaw", w.agent_start_yaw, -kPi, kPi);
}

void Validate(const WorldParams& w) {
  ValidateObjects(w);
  const double half = w.floor_size / 2;
  auto check_inside = [&](const std::string& name, const Vec2& p, double radius) {
    const double limit = half - radius;
    for (int k = 0; k < 2; ++k) {
      CheckRange(name + "[" + std::to_string(k) + "]", p[k], -limit, limit,
                 "inside the walls: floor_size / 2 - footprint radius " + Num(radius));
    }
  };
  check_inside("agent_start", w.agent_start, w.agent_radius);
  for (size_t i = 0; i < w.boxes.size(); ++i) {
    check_inside(BoxName(i) + ".start", w.boxes[i].start, FootprintRadius(w.boxes[i]));
  }
  // footprints must not overlap
  auto overlap = [&](const std::string& a, const Vec2& pa, double ra, const std::string& b,
                     const Vec2& pb, double rb) {
    const double d = Distance(pa, pb);
    if (d >= ra + rb) return;
    Fail(b + ".start must be at least " + Num(ra + rb) + " m (the sum of footprint radii) from " +
         a + ", got " + Num(d) + " m");
  };
  for (size_t i = 0; i < w.boxes.size(); ++i) {
    const BoxParams& bi = w.boxes[i];
    overlap("agent_start", w.agent_start, w.agent_radius, BoxName(i), bi.start,
            FootprintRadius(bi));
    for (size_t j = 0; j < i; ++j) {
      overlap(BoxName(j) + ".start", w.boxes[j].start, FootprintRadius(w.boxes[j]), BoxName(i),
              bi.start, FootprintRadius(bi));
    }
  }
  const double target_limit = half - w.success_radius;
  for (int k = 0; k < 2; ++k) {
    CheckRange("target[" + std::to_string(k) + "]", w.target[k], -target_limit, target_limit,
               "floor_size / 2 - success_radius");
  }
  auto far_enough = [&](const std::string& name, const Vec2& p) {
    const double d = Distance(p, w.target);
    if (d >= w.min_target_distance) return;
    Fail("target must be at least min_target_distance = " + Num(w.min_target_distance) +
         " m from " + name + ", got " + Num(d) + " m");
  };
  far_enough("agent_start", w.agent_start);
  for (size_t i = 0; i < w.boxes.size(); ++i) far_enough(BoxName(i) + ".start", w.boxes[i].start);
}

nlohmann::json ToJson(const WorldParams& w) {
  nlohmann::json boxes = nlohmann::json::array();
  for (const BoxParams& b : w.boxes) {
    boxes.push_back({{"shape", ShapeName(b.shape)},
                     {"size", b.size},
                     {"mass", b.mass},
                     {"friction", b.friction},
                     {"rgba", b.rgba},
                     {"start", b.start},
                     {"start_yaw", b.start_yaw}});
  }
  return {{"floor_size", w.floor_size},
          {"wall_height", w.wall_height},
          {"agent_radius", w.agent_radius},
          {"agent_force", w.agent_force},
          {"agent_torque", w.agent_torque},
          {"success_radius", w.success_radius},
          {"min_target_distance", w.min_target_distance},
          {"agent_start", w.agent_start},
          {"agent_start_yaw", w.agent_start_yaw},
          {"target", w.target},
          {"boxes", boxes}};
}

WorldParams WorldFromJson(const nlohmann::json& json) {
  const JsonObject o(json, "");
  o.ExpectKeys({"floor_size", "wall_height", "agent_radius", "agent_force", "agent_torque",
                "success_radius", "min_target_distance", "agent_start", "agent_start_yaw",
                "target", "boxes"});
  WorldParams w;
  w.floor_size = o.Number("floor_size");
  w.wall_height = o.Number("wall_height");
  w.agent_radius = o.Number("agent_radius");
  w.agent_force = o.Number("agent_force");
  w.agent_torque = o.Number("agent_torque");
  w.success_radius = o.Number("success_radius");
  w.min_target_distance = o.Number("min_target_distance");
  w.agent_start = o.Numbers<2>("agent_start");
  w.agent_start_yaw = o.Number("agent_start_yaw");
  w.target = o.Numbers<2>("target");
  const nlohmann::json& boxes = o.Field("boxes");
  if (!boxes.is_array()) Fail("boxes must be an array, got " + boxes.dump());
  if (boxes.size() > static_cast<size_t>(kMaxBoxesLimit)) {
    Fail("num_boxes must be in [0, " + std::to_string(kMaxBoxesLimit) + "], got " +
         std::to_string(boxes.size()));
  }
  for (size_t i = 0; i < boxes.size(); ++i) {
    const JsonObject b(boxes[i], BoxName(i));
    b.ExpectKeys({"shape", "size", "mass", "friction", "rgba", "start", "start_yaw"});
    BoxParams box;
    const std::string shape = b.String("shape");
    const std::optional<Shape> parsed = ParseShape(shape);
    if (!parsed) Fail(BoxName(i) + ".shape must be box, cylinder or sphere, got '" + shape + "'");
    box.shape = *parsed;
    box.size = b.Number("size");
    box.mass = b.Number("mass");
    box.friction = b.Number("friction");
    box.rgba = b.Numbers<4>("rgba");
    box.start = b.Numbers<2>("start");
    box.start_yaw = b.Number("start_yaw");
    w.boxes.push_back(box);
  }
  Validate(w);
  return w;
}

void PlaceObjects(WorldParams& w, Rng& rng, const StartRules& rules) {
  ValidateObjects(w);
  const double box_start_gap = rules.box_start_gap;
  const double half = w.floor_size / 2;
  struct Placed {
    Vec2 p;
    double r;
  };
  std::vector<Placed> placed;
  // A jammed sequential placement is retried from scratch a few times.
  constexpr int kRestarts = 10;
  for (int restart = 0; restart < kRestarts; ++restart) {
    placed.clear();
    const double a = half - w.agent_radius - kPlacementClearance;
    if (rules.agent_in_corner) {
      const double inset =
          std::max(kCornerInset * w.floor_size, w.agent_radius + kPlacementClearance);
      const double sx = rng.Uniform(0.0, 1.0) < 0.5 ? -1.0 : 1.0;
      const double sy = rng.Uniform(0.0, 1.0) < 0.5 ? -1.0 : 1.0;
      w.agent_start = {sx * (half - rng.Uniform(half - a, inset)),
                       sy * (half - rng.Uniform(half - a, inset))};
    } else {
      w.agent_start = {rng.Uniform(-a, a), rng.Uniform(-a, a)};
    }
    w.agent_start_yaw = rng.Uniform(-kPi, kPi);
    placed.push_back({w.agent_start, w.agent_radius});
    bool ok = true;
    for (BoxParams& b : w.boxes) {
      const double r = FootprintRadius(b);
      const double limit = half - r - kPlacementClearance;
      bool found = false;
      const double touching = w.agent_radius + r + kPlacementClearance;
      for (int t = 0; t < kPlacementTries && !found; ++t) {
        Vec2 p = {rng.Uniform(-limit, limit), rng.Uniform(-limit, limit)};
        if (box_start_gap >= 0) {
          const double angle =
              rules.agent_in_corner
                  ? std::atan2(-w.agent_start[1], -w.agent_start[0]) +
                        rng.Uniform(-kPi / 4, kPi / 4)
                  : rng.Uniform(-kPi, kPi);
          const double d = touching + rng.Uniform(0.0, box_start_gap);
          p = {w.agent_start[0] + d * std::cos(angle), w.agent_start[1] + d * std::sin(angle)};
          if (std::abs(p[0]) > limit || std::abs(p[1]) > limit) continue;
        }
        found = std::all_of(placed.begin(), placed.end(), [&](const Placed& q) {
          return Distance(p, q.p) >= r + q.r + kPlacementClearance;
        });
        if (found) b.start = p;
      }
      if (!found) {
        ok = false;
        break;
      }
      b.start_yaw = rng.Uniform(-kPi, kPi);
      placed.push_back({b.start, r});
    }
    if (ok) return;
  }
  Fail("could not place " + std::to_string(w.boxes.size()) + " boxes without overlap on a " +
       Num(w.floor_size) + " m floor" +
       (box_start_gap >= 0 ? " within box_start_gap = " + Num(box_start_gap) + " m of the agent"
                           : std::string()) +
       " in " + std::to_string(kRestarts) + " x " + std::to_string(kPlacementTries) +
       " tries; lower num_boxes or box_size, or raise floor_size" +
       (box_start_gap >= 0 ? " or box_start_gap" : ""));
}

void PlaceTarget(WorldParams& w, Rng& rng) {
  const double limit = w.floor_size / 2 - w.success_radius;
  for (int t = 0; t < kPlacementTries; ++t) {
    const Vec2 p = {rng.Uniform(-limit, limit), rng.Uniform(-limit, limit)};
    bool ok = Distance(p, w.agent_start) >= w.min_target_distance;
    for (const BoxParams& b : w.boxes) ok = ok && Distance(p, b.start) >= w.min_target_distance;
    if (ok) {
      w.target = p;
      return;
    }
  }
  Fail("could not place the target at least min_target_distance = " +
       Num(w.min_target_distance) + " m from the agent and " + std::to_string(w.boxes.size()) +
       " boxes in " + std::to_string(kPlacementTries) +
       " tries; lower min_target_distance_ratio or num_boxes, or raise floor_size");
}

void WorldDistribution::Validate() const {
  auto check_pair = [](const std::string& name, const Vec2& r, double low, double high,
                       const std::string& why) {
    CheckRange(name + " (min)", r[0], low, high, why);
    CheckRange(name + " (max)", r[1], low, high, why);
    if (r[0] > r[1]) Fail(name + ": min " + Num(r[0]) + " exceeds max " + Num(r[1]));
  };
  check_pair("floor_size", floor_size, kMinFloorSize, kMaxFloorSize, "");
  const double quarter = floor_size[0] / 4;
  if (num_boxes[0] < 0 || num_boxes[1] > kMaxBoxesLimit || num_boxes[0] > num_boxes[1]) {
    Fail("num_boxes must be in [0, " + std::to_string(kMaxBoxesLimit) + "] with min <= max, got " +
         std::to_string(num_boxes[0]) + ".." + std::to_string(num_boxes[1]));
  }
  if (box_shapes.empty()) Fail("box_shapes must name at least one of box, cylinder, sphere");
  check_pair("box_size", box_size, kMinObjectSize, quarter, "up to floor_size / 4");
  check_pair("box_mass", box_mass, kMinMass, kMaxMass, "");
  check_pair("box_friction", box_friction, 0.0, kMaxFriction, "");
  CheckRange("success_radius_ratio", success_radius_ratio, kMinObjectSize / floor_size[0], 0.25,
             "success_radius = ratio x floor_size, from 0.01 m up to floor_size / 4");
  CheckRange("min_target_distance_ratio", min_target_distance_ratio, success_radius_ratio,
             (1 - 2 * success_radius_ratio) / std::numbers::sqrt2,
             "success_radius_ratio to (1 - 2 success_radius_ratio) / sqrt(2)");
  if (starts.box_start_gap != -1.0) {
    CheckRange("box_start_gap", starts.box_start_gap, 0.0, floor_size[0],
               "-1 (anywhere) or a gap in m up to floor_size");
  }
  if (layout_seed < -1) Fail("layout_seed must be -1 (a layout per world) or >= 0, got " +
                             std::to_string(layout_seed));
  // the most crowded world: the most and largest boxes on the smallest floor
  WorldParams worst;
  worst.floor_size = floor_size[0];
  worst.wall_height = wall_height;
  worst.agent_radius = agent_radius;
  worst.agent_force = agent_force;
  worst.agent_torque = agent_torque;
  worst.success_radius = success_radius_ratio * floor_size[0];
  worst.min_target_distance = min_target_distance_ratio * floor_size[0];
  BoxParams largest;
  largest.shape = std::find(box_shapes.begin(), box_shapes.end(), Shape::kBox) != box_shapes.end()
                      ? Shape::kBox
                      : box_shapes.front();
  largest.size = box_size[1];
  largest.mass = box_mass[0];
  largest.friction = box_friction[0];
  worst.boxes.assign(static_cast<size_t>(num_boxes[1]), largest);
  ValidateObjects(worst);
}

WorldParams WorldDistribution::Sample(Rng& rng) const {
  // A crowded layout may leave no spot for the target: draw a new layout
  // (unless it is fixed) a few times before giving up.
  constexpr int kLayoutAttempts = 20;
  for (int attempt = 0;; ++attempt) {
    Rng fixed_layout(layout_seed >= 0 ? static_cast<uint64_t>(layout_seed) : 0);
    Rng& layout = layout_seed >= 0 ? fixed_layout : rng;
    WorldParams w;
    w.floor_size = layout.Uniform(floor_size[0], floor_size[1]);
    w.wall_height = wall_height;
    w.agent_radius = agent_radius;
    w.agent_force = agent_force;
    w.agent_torque = agent_torque;
    w.success_radius = success_radius_ratio * w.floor_size;
    w.min_target_distance = min_target_distance_ratio * w.floor_size;
    const int n = num_boxes[0] + static_cast<int>(layout.UniformInt(
                                     static_cast<uint64_t>(num_boxes[1] - num_boxes[0] + 1)));
    for (int i = 0; i < n; ++i) {
      BoxParams b;
      b.shape = box_shapes[layout.UniformInt(box_shapes.size())];
      b.size = layout.Uniform(box_size[0], box_size[1]);
      b.mass = layout.Uniform(box_mass[0], box_mass[1]);
      b.friction = layout.Uniform(box_friction[0], box_friction[1]);
      b.rgba =
          random_colors ? kPalette[layout.UniformInt(std::size(kPalette))] : ShapeColor(b.shape);
      w.boxes.push_back(b);
    }
    PlaceObjects(w, layout, starts);
    try {
      PlaceTarget(w, rng);
      return w;
    } catch (const ConfigError&) {
      if (layout_seed >= 0 || attempt + 1 == kLayoutAttempts) throw;
    }
  }
}

WorldParams GenerateWorld(const WorldDistribution& d, uint64_t seed) {
  Rng rng(seed);
  return d.Sample(rng);
}

}  // namespace manyworlds::boxworld
