// A small MJCF writer: builds a MuJoCo model description from code and
// compiles it in memory, for suites whose scenes are generated rather than
// written by hand (the box world makes one per task).
//
//   sim::MjcfBuilder b("arena");
//   b.option().Set("timestep", 0.005);
//   b.AddMaterial({.name = "floor", .rgba = {0.3, 0.3, 0.3, 1}});
//   sim::MjcfBody world = b.worldbody();
//   world.AddGeom({.name = "floor", .type = sim::GeomType::kPlane, .size = {5, 5, 0.1}});
//   sim::MjcfBody ball = world.AddBody("ball", {0, 0, 0.2});
//   ball.AddJoint({.name = "x", .type = sim::JointType::kSlide, .axis = {1, 0, 0}});
//   ball.AddGeom({.type = sim::GeomType::kSphere, .size = {0.2}});
//   b.AddMotor({.name = "x", .joint = "x", .ctrlrange = {-1, 1}});
//   sim::ModelPtr model = b.Build();   // MujocoError if MuJoCo rejects it
//
// MuJoCo 2.2.2's C API compiles models only from MJCF text (mj_loadXML,
// which reads from a virtual file system; there is no model-editing API
// before 3.2), so the builder writes text: ToXml() is the exact document
// Build() compiles. Numbers are written with 17 significant digits, so the
// compiled model holds exactly the doubles given here.
//
// The typed helpers cover what generated scenes need (bodies, the three
// solid primitives plus planes and capsules, slide/hinge/free joints, sites,
// cameras, lights, builtin textures, materials, motors). Anything else is
// reachable through MjcfElement::Set/AddChild on the element a helper
// returns, e.g. b.visual().AddChild("quality").Set("shadowsize", 4096).
#ifndef MANYWORLDS_SIM_MJCF_H_
#define MANYWORLDS_SIM_MJCF_H_

#include <array>
#include <initializer_list>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "manyworlds/sim/model.h"

namespace manyworlds::sim {

// One XML element with attributes (kept in insertion order) and children.
class MjcfElement {
 public:
  explicit MjcfElement(std::string tag) : tag_(std::move(tag)) {}
  MjcfElement(const MjcfElement&) = delete;
  MjcfElement& operator=(const MjcfElement&) = delete;
  // Moving keeps the children where they are (references to them stay valid).
  MjcfElement(MjcfElement&&) = default;
  MjcfElement& operator=(MjcfElement&&) = default;

  const std::string& tag() const { return tag_; }

  // Sets (or replaces) an attribute. Text is escaped when written; numbers
  // are written with 17 significant digits, lists separated by spaces.
  // Throws Error for a non-finite number.
  MjcfElement& Set(std::string_view name, std::string_view value);
  MjcfElement& Set(std::string_view name, const char* value) {
    return Set(name, std::string_view(value));
  }
  MjcfElement& Set(std::string_view name, double value);
  MjcfElement& Set(std::string_view name, int value) { return Set(name, static_cast<double>(value)); }
  MjcfElement& Set(std::string_view name, std::span<const double> values);
  MjcfElement& Set(std::string_view name, std::initializer_list<double> values) {
    return Set(name, std::span<const double>(values.begin(), values.size()));
  }
  // The attribute's text, if set.
  std::optional<std::string> Get(std::string_view name) const;

  // Appends a child element; the reference stays valid for the element's
  // lifetime.
  MjcfElement& AddChild(std::string tag);
  // The first child with this tag, created (appended) if there is none.
  MjcfElement& Child(std::string_view tag);
  const std::vector<std::unique_ptr<MjcfElement>>& children() const { return children_; }

  // Appends the element as indented XML.
  void Write(std::string* out, int depth) const;

 private:
  std::string tag_;
  std::vector<std::pair<std::string, std::string>> attributes_;
  std::vector<std::unique_ptr<MjcfElement>> children_;
};

enum class GeomType { kPlane, kBox, kSphere, kCylinder, kCapsule };
enum class JointType { kSlide, kHinge, kFree };

// MJCF's name for a geom or joint type ("box", "slide", ...).
const char* MjcfName(GeomType type);
const char* MjcfName(JointType type);

using Vec3 = std::array<double, 3>;
using Rgba = std::array<double, 4>;

// Optional fields are written only when set, so MuJoCo's defaults (or the
// model's <default> class) apply otherwise.
struct MjcfGeom {
  std::string name{};  // empty: unnamed
  GeomType type = GeomType::kSphere;
  // MuJoCo's size convention: plane (x half, y half, grid spacing), box (3
  // half-extents), sphere (radius), cylinder and capsule (radius, half-length).
  std::vector<double> size{};
  Vec3 pos = {0, 0, 0};
  std::optional<std::array<double, 4>> quat{};  // w x y z
  std::optional<Rgba> rgba{};
  std::string material{};
  std::optional<double> mass{};      // kg; else density 1000
  std::optional<Vec3> friction{};    // sliding, torsional, rolling
  std::optional<int> contype{};
  std::optional<int> conaffinity{};
  std::optional<int> condim{};
  std::optional<int> group{};        // visualisation group
};

struct MjcfJoint {
  std::string name{};
  JointType type = JointType::kHinge;
  Vec3 axis = {0, 0, 1};  // ignored for kFree
  std::optional<double> damping{};
  std::optional<double> armature{};
  std::optional<std::array<double, 2>> range{};  // limited when set
};

struct MjcfSite {
  std::string name{};
  GeomType type = GeomType::kSphere;
  std::vector<double> size{};
  Vec3 pos = {0, 0, 0};
  std::optional<Rgba> rgba{};
  std::optional<int> group{};
};

// A fixed camera in its parent body's frame.
struct MjcfCamera {
  std::string name{};
  Vec3 pos = {0, 0, 0};
  // Orientation as the image's right (x) and up (y) axes in the parent
  // frame; LookAt() computes them.
  std::array<double, 6> xyaxes = {1, 0, 0, 0, 1, 0};
  double fovy = 45;  // vertical field of view, degrees

  // A camera at `pos` looking at `target` with the world's +z up in the
  // image (the view direction must not be vertical; a top-down camera
  // should set xyaxes directly).
  static MjcfCamera LookAt(std::string name, const Vec3& pos, const Vec3& target, double fovy = 45);
};

struct MjcfLight {
  std::string name{};
  Vec3 pos = {0, 0, 3};
  Vec3 dir = {0, 0, -1};
  Vec3 diffuse = {0.7, 0.7, 0.7};
  Vec3 specular = {0.3, 0.3, 0.3};
  bool directional = false;
  bool castshadow = true;
};

// A builtin (procedural) texture, so no image files are needed.
struct MjcfTexture {
  std::string name{};
  std::string type = "2d";        // 2d, cube, skybox
  std::string builtin = "checker";  // checker, gradient, flat
  Vec3 rgb1 = {0.2, 0.2, 0.2};
  Vec3 rgb2 = {0.3, 0.3, 0.3};
  int width = 256;
  int height = 256;
  std::string mark{};               // "", edge, cross, random
  std::optional<Vec3> markrgb{};
};

struct MjcfMaterial {
  std::string name{};
  std::string texture{};            // empty: none
  std::optional<std::array<double, 2>> texrepeat{};
  bool texuniform = false;
  std::optional<Rgba> rgba{};
  std::optional<double> specular{};
  std::optional<double> shininess{};
  std::optional<double> reflectance{};
};

// A motor on a joint: force (or torque) = gear * ctrl, ctrl clamped to
// ctrlrange.
struct MjcfMotor {
  std::string name{};
  std::string joint{};
  double gear = 1;
  std::array<double, 2> ctrlrange = {-1, 1};
};

// A handle on a <body> (or <worldbody>) element of a builder; valid as long
// as the builder is.
class MjcfBody {
 public:
  explicit MjcfBody(MjcfElement& element) : element_(&element) {}

  MjcfBody AddBody(std::string_view name, const Vec3& pos);
  MjcfElement& AddGeom(const MjcfGeom& geom);
  MjcfElement& AddJoint(const MjcfJoint& joint);
  MjcfElement& AddSite(const MjcfSite& site);
  MjcfElement& AddCamera(const MjcfCamera& camera);
  MjcfElement& AddLight(const MjcfLight& light);
  MjcfElement& element() { return *element_; }

 private:
  MjcfElement* element_;
};

class MjcfBuilder {
 public:
  // Starts the document with <compiler angle="radian">: every angle given to
  // the builder (joint ranges, euler orientations) is in radians. Throws
  // Error for an empty name.
  explicit MjcfBuilder(std::string model_name);

  // The top-level sections, each created (appended) on first use.
  MjcfElement& compiler() { return root_.Child("compiler"); }
  MjcfElement& option() { return root_.Child("option"); }
  MjcfElement& size() { return root_.Child("size"); }
  MjcfElement& visual() { return root_.Child("visual"); }
  MjcfElement& defaults() { return root_.Child("default"); }
  MjcfElement& asset() { return root_.Child("asset"); }
  MjcfBody worldbody() { return MjcfBody(root_.Child("worldbody")); }
  MjcfElement& actuator() { return root_.Child("actuator"); }

  MjcfElement& AddTexture(const MjcfTexture& texture);
  MjcfElement& AddMaterial(const MjcfMaterial& material);
  MjcfElement& AddMotor(const MjcfMotor& motor);

  // The complete MJCF document.
  std::string ToXml() const;
  // Compiles ToXml() in memory (sim::LoadModelFromString, under the name
  // "<model_name>.xml"). Throws MujocoError with MuJoCo's message.
  ModelPtr Build() const;

 private:
  std::string name_;
  MjcfElement root_{"mujoco"};
};

}  // namespace manyworlds::sim

#endif  // MANYWORLDS_SIM_MJCF_H_
