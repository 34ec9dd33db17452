#include "manyworlds/boxworld/boxworld.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "manyworlds/core/error.h"

namespace manyworlds {
namespace boxworld {
namespace {

// [value, value_max], value_max = -1 meaning the fixed value.
Vec2 FloatRange(const Options& o, const std::string& name) {
  const double low = o.Float(name);
  const double high = o.Float(name + "_max");
  return {low, high == -1.0 ? low : high};
}

std::vector<Shape> ParseShapes(const std::string& env_id, const std::string& text) {
  std::vector<Shape> shapes;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    item.erase(0, item.find_first_not_of(' '));
    item.erase(item.find_last_not_of(' ') + 1);
    const std::optional<Shape> shape = ParseShape(item);
    if (!shape) {
      throw ConfigError("env '" + env_id + "': option 'box_shapes' takes a comma-separated list " +
                        "of box, cylinder, sphere; got '" + ShortenForMessage(text) + "'");
    }
    if (std::find(shapes.begin(), shapes.end(), *shape) == shapes.end()) shapes.push_back(*shape);
  }
  if (shapes.empty()) {
    throw ConfigError("env '" + env_id + "': option 'box_shapes' must name at least one of box, " +
                      "cylinder, sphere");
  }
  return shapes;
}

std::vector<OptionSpec> BoxWorldOptions() {
  const WorldDistribution d;
  return {
      {"floor_size", OptionType::kFloat, d.floor_size[0],
       "side of the square floor in m, [1, 100]; the lower end of the range with floor_size_max"},
      {"floor_size_max", OptionType::kFloat, -1.0,
       "upper end of the floor_size range (drawn uniformly); -1: fixed at floor_size"},
      {"num_boxes", OptionType::kInt, int64_t{d.num_boxes[0]},
       "number of boxes, [0, 64] ([1, 64] for the complex task); lower end with num_boxes_max"},
      {"num_boxes_max", OptionType::kInt, int64_t{-1},
       "upper end of the num_boxes range (uniform); -1: fixed at num_boxes; <= max_boxes"},
      {"box_shapes", OptionType::kString, std::string("box"),
       "shapes drawn (uniformly) for each box: a comma-separated list of box, cylinder, sphere"},
      {"box_size", OptionType::kFloat, d.box_size[0],
       "half-extent of a box, radius of a cylinder or sphere, in m, [0.01, floor_size / 4]; "
       "lower end with box_size_max"},
      {"box_size_max", OptionType::kFloat, -1.0, "upper end of the box_size range; -1: fixed"},
      {"box_mass", OptionType::kFloat, d.box_mass[0], "box mass in kg, [0.001, 1000]"},
      {"box_mass_max", OptionType::kFloat, -1.0, "upper end of the box_mass range; -1: fixed"},
      {"box_friction", OptionType::kFloat, d.box_friction[0],
       "box sliding friction coefficient, [0, 10]"},
      {"box_friction_max", OptionType::kFloat, -1.0,
       "upper end of the box_friction range; -1: fixed"},
      {"random_colors", OptionType::kBool, d.random_colors,
       "draw each box's colour from a palette of 8 (else one colour per shape)"},
      {"wall_height", OptionType::kFloat, d.wall_height, "wall height in m, [0.05, 10]"},
      {"agent_radius", OptionType::kFloat, d.agent_radius,
       "agent sphere radius in m, [0.01, floor_size / 4]"},
      {"agent_force", OptionType::kFloat, d.agent_force,
       "force in N on x and y at action +-1, (0, 50]; top speed = agent_force / 2.5 m/s"},
      {"agent_torque", OptionType::kFloat, d.agent_torque,
       "torque in N m about z at action +-1, (0, 10]"},
      {"success_radius_ratio", OptionType::kFloat, d.success_radius_ratio,
       "success radius (reach, delivery) as a fraction of floor_size, up to 0.25 (the study: "
       "1 m on 5 m = 0.2)"},
      {"min_target_distance_ratio", OptionType::kFloat, d.min_target_distance_ratio,
       "minimum target distance from the agent and every box start, as a fraction of "
       "floor_size, [success_radius_ratio, (1 - 2 success_radius_ratio) / sqrt(2)]"},
      {"agent_start", OptionType::kString, std::string("anywhere"),
       "anywhere, or corner: a random corner, up to 0.15 x floor_size from both walls (the "
       "study's code: 0.55 m on its 5 m floor)",
       {"anywhere", "corner"}},
      {"box_start_gap", OptionType::kFloat, d.starts.box_start_gap,
       "-1: boxes start anywhere; >= 0: every box starts at most this many m (footprint to "
       "footprint) from the agent, at a random angle, or with agent_start=corner facing the "
       "floor's centre (the study's code starts its cube touching the agent, in front), "
       "[0, floor_size]"},
      {"layout_seed", OptionType::kInt, int64_t{-1},
       "-1: every task is a new world; >= 0: every task shares the layout (floor, boxes, "
       "starts) drawn from this seed and only the target varies"},
      {"targets_per_layout", OptionType::kInt, int64_t{1},
       ">= 1; > 1: groups of this many consecutive task draws share one layout (drawn per "
       "group) and differ only in the target (the study's support and query tasks); needs "
       "layout_seed = -1"},
      {"target_in_obs", OptionType::kBool, false,
       "append the target x, y (zeros with hide_target) to the env observation, for learners "
       "that read only env_obs (the study's observation holds the target)"},
      {"max_boxes", OptionType::kInt, int64_t{8},
       "box slots in the observation (masked), [1, 64]; keep it equal across envs that share a "
       "policy"},
      {"hide_target", OptionType::kBool, false,
       "if true (meta-RL) the task observation (the target) is zero: infer it from rewards"},
      {"throw_on_sim_warning", OptionType::kBool, false,
       "throw on a MuJoCo warning instead of ending the episode"}};
}

std::unique_ptr<Env> MakeBoxWorld(BoxTask task, const Options& o) {
  const std::string id = BoxWorldEnv::IdOf(task);
  BoxWorldEnv::Config config;
  config.task = task;
  WorldDistribution& d = config.distribution;
  d.floor_size = FloatRange(o, "floor_size");
  const int64_t n = o.Int("num_boxes");
  const int64_t n_max = o.Int("num_boxes_max") == -1 ? n : o.Int("num_boxes_max");
  auto small_int = [&](const char* name, int64_t v) {
    if (v < -1 || v > kMaxBoxesLimit) {
      throw ConfigError("env '" + id + "': option '" + name + "' must be in [0, " +
                        std::to_string(kMaxBoxesLimit) + "], got " + std::to_string(v));
    }
    return static_cast<int>(v);
  };
  d.num_boxes = {small_int("num_boxes", n), small_int("num_boxes_max", n_max)};
  d.box_shapes = ParseShapes(id, o.String("box_shapes"));
  d.box_size = FloatRange(o, "box_size");
  d.box_mass = FloatRange(o, "box_mass");
  d.box_friction = FloatRange(o, "box_friction");
  d.random_colors = o.Bool("random_colors");
  d.wall_height = o.Float("wall_height");
  d.agent_radius = o.Float("agent_radius");
  d.agent_force = o.Float("agent_force");
  d.agent_torque = o.Float("agent_torque");
  d.success_radius_ratio = o.Float("success_radius_ratio");
  d.min_target_distance_ratio = o.Float("min_target_distance_ratio");
  d.starts.box_start_gap = o.Float("box_start_gap");
  d.starts.agent_in_corner = o.String("agent_start") == "corner";  // the registry checked it
  d.layout_seed = o.Int("layout_seed");
  const int64_t max_boxes = o.Int("max_boxes");
  if (max_boxes < 1 || max_boxes > kMaxBoxesLimit) {
    throw ConfigError("env '" + id + "': option 'max_boxes' must be in [1, " +
                      std::to_string(kMaxBoxesLimit) + "], got " + std::to_string(max_boxes));
  }
  config.max_boxes = static_cast<int>(max_boxes);
  config.hide_target = o.Bool("hide_target");
  config.target_in_obs = o.Bool("target_in_obs");
  config.targets_per_layout = o.Int("targets_per_layout");
  config.throw_on_sim_warning = o.Bool("throw_on_sim_warning");
  return std::make_unique<BoxWorldEnv>(config);
}

}  // namespace
}  // namespace boxworld

void RegisterBoxWorldSuite(Registry& registry) {
  using boxworld::BoxTask;
  for (const BoxTask task : {BoxTask::kSimple, BoxTask::kComplex}) {
    const bool simple = task == BoxTask::kSimple;
    registry.Add(EnvRegistration{
        boxworld::BoxWorldEnv::IdOf(task), "boxworld",
        simple ? "Generated walled floors with boxes (MuJoCo); reach the target"
               : "Generated walled floors with boxes (MuJoCo); push every box to the target",
        boxworld::BoxWorldOptions(), [task](const Options& o) -> std::unique_ptr<Env> {
          return boxworld::MakeBoxWorld(task, o);
        }});
  }
}

}  // namespace manyworlds
