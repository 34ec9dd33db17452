// The box world's parameters and its generator.
//
// A world is a square floor of side `floor_size` centred on the origin,
// closed by four walls; an agent (a sphere with a nose that shows its
// heading) that slides in x and y and turns about z; boxes of three shapes
// (box, cylinder, sphere) that can be pushed; and a target on the floor.
// WorldParams holds everything that defines one world, start positions and
// target included, and is the envs' task state (ToJson/WorldFromJson).
//
// The generator (WorldDistribution) draws worlds from ranges. A world is a
// pure function of the distribution and a seed: GenerateWorld(d, seed).
// Start positions are rejection-sampled (bounded tries) so that footprints
// (the bounding circle of each object seen from above) do not overlap and
// stay inside the walls; the target keeps `min_target_distance` from the
// agent and from every box.
//
// Every bad value raises a one-line ConfigError naming the parameter and its
// allowed range, e.g.
//   "box world: boxes[1].size must be in [0.01, 1.25] (floor_size / 4), got -0.2".
#ifndef MANYWORLDS_BOXWORLD_WORLD_H_
#define MANYWORLDS_BOXWORLD_WORLD_H_

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "manyworlds/core/rng.h"

namespace manyworlds::boxworld {

enum class Shape { kBox, kCylinder, kSphere };

// "box", "cylinder", "sphere".
const char* ShapeName(Shape shape);
std::optional<Shape> ParseShape(std::string_view name);

using Vec2 = std::array<double, 2>;
using Rgba = std::array<double, 4>;

struct BoxParams {
  Shape shape = Shape::kBox;
  // Half-extent of a box's edges, radius of a cylinder or sphere (metres).
  // A cylinder's half-height equals its radius.
  double size = 0.125;
  double mass = 0.05;      // kg
  double friction = 0.2;   // sliding friction against floor, walls, agent
  Rgba rgba = {0.55, 0.55, 0.6, 1.0};
  Vec2 start = {0.0, 0.0};  // centre, world frame
  double start_yaw = 0.0;   // radians about z

  bool operator==(const BoxParams&) const = default;
};

// Validation ranges (the ConfigErrors quote them).
inline constexpr double kMinFloorSize = 1.0;
inline constexpr double kMaxFloorSize = 100.0;
inline constexpr double kMinWallHeight = 0.05;
inline constexpr double kMaxWallHeight = 10.0;
inline constexpr double kMinObjectSize = 0.01;  // agent radius, box size
// The agent's gains. At 50 N the top speed is 20 m/s (10 cm per physics
// step) and the joint limits at the walls hold the agent inside the walls'
// outer faces (a 0.01 m agent pressed 5 cm into a wall); at 100 N it got past
// them, at 10,000 N (4 km/s) 2 m past.
inline constexpr double kMaxAgentForce = 50.0;  // N
inline constexpr double kMaxAgentTorque = 10.0;  // N m
inline constexpr double kMinMass = 1e-3;
inline constexpr double kMaxMass = 1e3;
inline constexpr double kMaxFriction = 10.0;
inline constexpr int kMaxBoxesLimit = 64;
// At most this fraction of the floor may be covered by the footprints
// (squares around the bounding circles, clearance included) of the agent
// and the boxes; beyond it random placement rarely succeeds.
inline constexpr double kMaxFill = 0.5;
// Gap kept between sampled footprints and to the walls (metres).
inline constexpr double kPlacementClearance = 0.02;
inline constexpr int kPlacementTries = 1000;  // per object

struct WorldParams {
  double floor_size = 5.0;     // side of the square floor inside the walls (m)
  double wall_height = 0.625;  // m
  double agent_radius = 0.15;  // m
  // Actuator gains: the force on x and y (N) and the torque about z (N m)
  // at action +-1. The agent's top speed is agent_force / 2.5 m/s.
  double agent_force = 5.0;
  double agent_torque = 0.5;
  // Reaching (simple task) and delivery (complex task) succeed at a distance
  // below success_radius; targets are drawn at least min_target_distance
  // from the agent and every box. The generator scales both with the floor
  // (0.2 x floor_size: the study's 1 m on its 5 m floor).
  double success_radius = 1.0;
  double min_target_distance = 1.0;
  Vec2 agent_start = {0.0, 0.0};
  double agent_start_yaw = 0.0;
  Vec2 target = {1.5, 1.5};
  std::vector<BoxParams> boxes = {};

  bool operator==(const WorldParams&) const = default;
};

// Radius of the bounding circle of a box seen from above.
double FootprintRadius(const BoxParams& box);
// Checks every field, start positions and target included. Throws
// ConfigError naming the first bad field and its allowed range.
void Validate(const WorldParams& world);
// Checks the fields that do not concern positions (sizes, masses, gains,
// thresholds, the number of boxes and whether they fit).
void ValidateObjects(const WorldParams& world);

// {"floor_size", "wall_height", "agent_radius", "agent_force",
//  "agent_torque", "success_radius", "min_target_distance",
//  "agent_start": [x, y], "agent_start_yaw", "target": [x, y],
//  "boxes": [{"shape", "size", "mass", "friction", "rgba": [r, g, b, a],
//             "start": [x, y], "start_yaw"}]}
nlohmann::json ToJson(const WorldParams& world);
// Parses and Validate()s. Throws ConfigError naming the field (missing,
// unknown, wrong type or out of range).
WorldParams WorldFromJson(const nlohmann::json& json);

// Where the generator starts the agent and the boxes.
struct StartRules {
  // false: the agent starts anywhere. true: in a random corner, each
  // coordinate between agent_radius and kCornerInset x floor_size from its
  // wall (the study's code: 0.55 m from both walls of its 5 m floor).
  bool agent_in_corner = false;
  // -1: boxes start anywhere. >= 0 (m): every box starts next to the agent,
  // the gap between their footprints uniform in [kPlacementClearance,
  // kPlacementClearance + box_start_gap], at a random angle, or with
  // agent_in_corner within 45 degrees of the direction to the floor's
  // centre (the study's cube sits on the diagonal in front of the agent).
  double box_start_gap = -1.0;
};
inline constexpr double kCornerInset = 0.15;

// Places the agent and the boxes (start positions and yaws) of `world`
// uniformly at random without overlap, by `rules`. Throws ConfigError if
// the objects cannot fit (ValidateObjects) or no placement is found in
// kPlacementTries tries per object.
void PlaceObjects(WorldParams& world, Rng& rng, const StartRules& rules = {});
// Draws the target uniformly in the target area (the floor shrunk by
// success_radius on every side: the study's [1, 4]^2 on its [0, 5]^2 floor)
// at least min_target_distance from the agent and every box. Throws
// ConfigError if none is found in kPlacementTries tries.
void PlaceTarget(WorldParams& world, Rng& rng);

// Ranges the generator draws from; every range is [min, max] (equal ends:
// fixed). Defaults: the study's world (5 m floor, one 0.25 m cube of 50 g).
struct WorldDistribution {
  Vec2 floor_size = {5.0, 5.0};
  std::array<int, 2> num_boxes = {1, 1};
  std::vector<Shape> box_shapes = {Shape::kBox};  // drawn uniformly per box
  Vec2 box_size = {0.125, 0.125};
  Vec2 box_mass = {0.05, 0.05};
  Vec2 box_friction = {0.2, 0.2};
  // Colour per box: false: a fixed colour per shape; true: drawn from a
  // palette of 8.
  bool random_colors = false;
  double wall_height = 0.625;
  double agent_radius = 0.15;
  double agent_force = 5.0;
  double agent_torque = 0.5;
  // success_radius and min_target_distance as fractions of floor_size.
  double success_radius_ratio = 0.2;
  double min_target_distance_ratio = 0.2;
  // -1: every world gets its own layout (floor, boxes, starts). >= 0: every
  // world shares the layout drawn from this seed and only the target varies
  // (the study's support/query tasks of one round).
  int64_t layout_seed = -1;
  // Start positions (StartRules): the options agent_start ("anywhere" or
  // "corner") and box_start_gap. The study's complex task starts the agent
  // in a corner with its box touching it, in front, as the study's code
  // does: every push then moves the box toward the room (and the target).
  StartRules starts;

  // Throws ConfigError naming the option ("num_boxes", "box_size", ...) and
  // its allowed range, including worlds of the largest sizes that cannot
  // fit on the smallest floor.
  void Validate() const;
  // Draws one world (layout from layout_seed if set, else from rng; target
  // from rng). A layout that leaves no room for the target (crowded floors:
  // every box keeps min_target_distance from it too) is drawn again, up to
  // 20 times, which favours fewer boxes on crowded settings; then, or at
  // once for a fixed layout, ConfigError.
  WorldParams Sample(Rng& rng) const;
};

// The world for a seed: d.Sample(Rng(seed)).
WorldParams GenerateWorld(const WorldDistribution& d, uint64_t seed);

}  // namespace manyworlds::boxworld

#endif  // MANYWORLDS_BOXWORLD_WORLD_H_
