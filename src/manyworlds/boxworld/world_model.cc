#include "manyworlds/boxworld/world_model.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace manyworlds::boxworld {
namespace {

// Collision bits: the floor (1) meets boxes only; the agent (2) meets boxes
// and walls; boxes and walls (3) meet everything.
constexpr int kFloorBits = 1;
constexpr int kAgentBits = 2;
constexpr int kSolidBits = 3;

sim::GeomType GeomOf(Shape shape) {
  switch (shape) {
    case Shape::kBox: return sim::GeomType::kBox;
    case Shape::kCylinder: return sim::GeomType::kCylinder;
    case Shape::kSphere: return sim::GeomType::kSphere;
  }
  return sim::GeomType::kBox;
}

std::vector<double> GeomSize(const BoxParams& b) {
  switch (b.shape) {
    case Shape::kBox: return {b.size, b.size, b.size};
    case Shape::kCylinder: return {b.size, b.size};
    case Shape::kSphere: return {b.size};
  }
  return {b.size};
}

}  // namespace

int ContactCapacity(const WorldParams& w) {
  return std::max(100, 50 + 6 * static_cast<int>(w.boxes.size()));
}

int ConstraintCapacity(const WorldParams& w) { return std::max(500, 4 * ContactCapacity(w)); }

sim::MjcfBuilder WorldMjcf(const WorldParams& w) {
  sim::MjcfBuilder b("box_world");
  b.option().Set("timestep", kTimestep);
  b.size().Set("nconmax", ContactCapacity(w)).Set("njmax", ConstraintCapacity(w));
  sim::MjcfElement& quality = b.visual().AddChild("quality");
  quality.Set("shadowsize", 4096);
  b.visual().AddChild("headlight").Set("ambient", {0.35, 0.35, 0.35}).Set("diffuse",
                                                                          {0.4, 0.4, 0.4});

  const double half = w.floor_size / 2;
  b.AddTexture({.name = "sky", .type = "skybox", .builtin = "gradient", .rgb1 = {0.6, 0.7, 0.8},
                .rgb2 = {0.1, 0.12, 0.15}, .width = 32, .height = 32});
  b.AddTexture({.name = "grid", .builtin = "checker", .rgb1 = {0.32, 0.34, 0.37},
                .rgb2 = {0.26, 0.28, 0.31}, .width = 64, .height = 64, .mark = "edge",
                .markrgb = sim::Vec3{0.4, 0.42, 0.45}});
  // texrepeat counts checker tiles (2 squares each) per floor: 1 m squares
  b.AddMaterial({.name = "floor", .texture = "grid",
                 .texrepeat = std::array<double, 2>{half, half}, .reflectance = 0.05});
  b.AddMaterial({.name = "wall", .rgba = sim::Rgba{0.5, 0.42, 0.35, 1}});

  sim::MjcfBody world = b.worldbody();
  world.AddLight({.name = "sun", .pos = {0, 0, 2 * w.floor_size}, .dir = {0, 0, -1},
                  .diffuse = {0.6, 0.6, 0.6}, .directional = true});
  world.AddGeom({.name = "floor", .type = sim::GeomType::kPlane,
                 .size = {half + kWallThickness, half + kWallThickness, 0.1},
                 .material = "floor", .friction = sim::Vec3{0, 0.005, 0.0001},
                 .contype = kFloorBits, .conaffinity = kFloorBits});
  const double wh = w.wall_height / 2;
  const double wo = half + kWallThickness / 2;
  const double wl = half + kWallThickness;
  struct Wall {
    const char* name;
    sim::Vec3 pos;
    std::vector<double> size;
  };
  const Wall walls[] = {{"wall_+x", {wo, 0, wh}, {kWallThickness / 2, wl, wh}},
                        {"wall_-x", {-wo, 0, wh}, {kWallThickness / 2, wl, wh}},
                        {"wall_+y", {0, wo, wh}, {wl, kWallThickness / 2, wh}},
                        {"wall_-y", {0, -wo, wh}, {wl, kWallThickness / 2, wh}}};
  for (const Wall& wall : walls) {
    world.AddGeom({.name = wall.name, .type = sim::GeomType::kBox, .size = wall.size,
                   .pos = wall.pos, .material = "wall", .friction = sim::Vec3{0, 0.005, 0.0001},
                   .contype = kSolidBits, .conaffinity = kSolidBits});
  }
  world.AddSite({.name = "target", .type = sim::GeomType::kCylinder,
                 .size = {w.success_radius, 0.002}, .pos = {w.target[0], w.target[1], 0.002},
                 .rgba = sim::Rgba{0.15, 0.35, 0.95, 0.45}});

  // cameras: top fits the floor and walls in a 45 degree field of view
  const double fovy = 45;
  const double top_height = (half + 2 * kWallThickness) / std::tan(fovy / 2 * std::numbers::pi / 180);
  world.AddCamera({.name = "top", .pos = {0, 0, top_height + w.wall_height},
                   .xyaxes = {1, 0, 0, 0, 1, 0}, .fovy = fovy});
  // "front" repeats "perspective" so that render's default camera (a preset
  // framed for the Sawyer scenes) frames this world instead
  for (const char* name : {"perspective", "front"}) {
    world.AddCamera(sim::MjcfCamera::LookAt(name, {0, -1.05 * w.floor_size, 1.25 * w.floor_size},
                                            {0, -0.05 * w.floor_size, 0}, fovy));
  }

  // The slide joints end at the walls: a fast, small agent pressing a box
  // into a wall was squeezed through it within one physics step; a joint
  // limit is not a collision and holds at any speed.
  sim::MjcfBody agent = world.AddBody("agent", {0, 0, w.agent_radius});
  const double reach = half - w.agent_radius;
  agent.AddJoint({.name = "agent_x", .type = sim::JointType::kSlide, .axis = {1, 0, 0},
                  .damping = kAgentDamping, .range = std::array<double, 2>{-reach, reach}});
  agent.AddJoint({.name = "agent_y", .type = sim::JointType::kSlide, .axis = {0, 1, 0},
                  .damping = kAgentDamping, .range = std::array<double, 2>{-reach, reach}});
  agent.AddJoint({.name = "agent_yaw", .type = sim::JointType::kHinge, .axis = {0, 0, 1},
                  .damping = kAgentYawDamping});
  agent.AddGeom({.name = "agent", .type = sim::GeomType::kSphere, .size = {w.agent_radius},
                 .rgba = sim::Rgba{0.85, 0.2, 0.2, 1}, .mass = kAgentMass,
                 .contype = kAgentBits, .conaffinity = kAgentBits});
  agent.AddGeom({.name = "agent_nose", .type = sim::GeomType::kSphere,
                 .size = {0.35 * w.agent_radius}, .pos = {0.8 * w.agent_radius, 0, 0},
                 .rgba = sim::Rgba{0.95, 0.85, 0.85, 1}, .mass = 0.01 * kAgentMass,
                 .contype = kAgentBits, .conaffinity = kAgentBits});

  for (size_t i = 0; i < w.boxes.size(); ++i) {
    const BoxParams& box = w.boxes[i];
    const std::string name = "box" + std::to_string(i);
    sim::MjcfBody body = world.AddBody(name, {box.start[0], box.start[1], box.size});
    body.AddJoint({.name = name, .type = sim::JointType::kFree, .damping = 0.01});
    body.AddGeom({.name = name, .type = GeomOf(box.shape), .size = GeomSize(box),
                  .rgba = box.rgba, .mass = box.mass,
                  .friction = sim::Vec3{box.friction, 0.005, 0.0001}, .contype = kSolidBits,
                  .conaffinity = kSolidBits, .condim = 3});
  }

  b.AddMotor({.name = "agent_x", .joint = "agent_x", .gear = 1,
              .ctrlrange = {-w.agent_force, w.agent_force}});
  b.AddMotor({.name = "agent_y", .joint = "agent_y", .gear = 1,
              .ctrlrange = {-w.agent_force, w.agent_force}});
  b.AddMotor({.name = "agent_yaw", .joint = "agent_yaw", .gear = 1,
              .ctrlrange = {-w.agent_torque, w.agent_torque}});
  return b;
}

sim::ModelPtr BuildWorldModel(const WorldParams& world) { return WorldMjcf(world).Build(); }

bool SameStructure(const WorldParams& a, const WorldParams& b) {
  if (a.floor_size != b.floor_size || a.wall_height != b.wall_height ||
      a.agent_radius != b.agent_radius || a.agent_force != b.agent_force ||
      a.agent_torque != b.agent_torque || a.success_radius != b.success_radius ||
      a.boxes.size() != b.boxes.size()) {
    return false;
  }
  for (size_t i = 0; i < a.boxes.size(); ++i) {
    const BoxParams& x = a.boxes[i];
    const BoxParams& y = b.boxes[i];
    if (x.shape != y.shape || x.size != y.size || x.mass != y.mass || x.friction != y.friction ||
        x.rgba != y.rgba) {
      return false;
    }
  }
  return true;
}

}  // namespace manyworlds::boxworld
