// The MJCF builder: what it writes, and that MuJoCo compiles it into the
// model the code describes (names, types, exact numbers, actuators).
#include "manyworlds/sim/mjcf.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "manyworlds/core/error.h"
#include "manyworlds/sim/mujoco_error.h"

namespace manyworlds::sim {
namespace {

MjcfBuilder Scene() {
  MjcfBuilder b("scene");
  b.option().Set("timestep", 0.004);
  b.AddTexture({.name = "grid", .builtin = "checker"});
  b.AddMaterial({.name = "floor", .texture = "grid", .texrepeat = std::array<double, 2>{2, 2}});
  MjcfBody world = b.worldbody();
  world.AddLight({.name = "sun"});
  world.AddGeom({.name = "floor", .type = GeomType::kPlane, .size = {2, 2, 0.1},
                 .material = "floor"});
  world.AddCamera(MjcfCamera::LookAt("persp", {0, -3, 2}, {0, 0, 0}));
  world.AddSite({.name = "mark", .type = GeomType::kCylinder, .size = {0.3, 0.01},
                 .pos = {0.1, 0.2, 0.0}});
  MjcfBody ball = world.AddBody("ball", {0, 0, 0.2});
  ball.AddJoint({.name = "x", .type = JointType::kSlide, .axis = {1, 0, 0}, .damping = 1.5});
  ball.AddJoint({.name = "yaw", .type = JointType::kHinge, .axis = {0, 0, 1},
                 .range = std::array<double, 2>{-1, 1}});
  ball.AddGeom({.name = "ball", .type = GeomType::kSphere, .size = {0.2}, .mass = 0.7});
  MjcfBody crate = world.AddBody("crate", {0.1 + 0.2, 0, 0.1});  // 0.30000000000000004
  crate.AddJoint({.name = "crate", .type = JointType::kFree});
  crate.AddGeom({.name = "crate", .type = GeomType::kBox, .size = {0.1, 0.1, 0.1},
                 .friction = Vec3{0.3, 0.005, 0.0001}});
  MjcfBody can = world.AddBody("can", {-0.5, 0, 0.1});
  can.AddJoint({.name = "can", .type = JointType::kFree});
  can.AddGeom({.name = "can", .type = GeomType::kCylinder, .size = {0.1, 0.1}});
  b.AddMotor({.name = "x", .joint = "x", .gear = 2, .ctrlrange = {-3, 3}});
  return b;
}

TEST(MjcfTest, BuildsTheModelTheCodeDescribes) {
  const MjcfBuilder b = Scene();
  ModelPtr m = b.Build();
  EXPECT_EQ(m->opt.timestep, 0.004);
  EXPECT_EQ(m->nbody, 4);  // world, ball, crate, can
  EXPECT_EQ(m->njnt, 4);
  EXPECT_EQ(m->nq, 2 + 7 + 7);
  EXPECT_EQ(m->nu, 1);
  EXPECT_EQ(m->ncam, 1);
  EXPECT_EQ(m->nlight, 1);
  EXPECT_EQ(m->nsite, 1);
  EXPECT_EQ(m->nmat, 1);
  EXPECT_EQ(m->ntex, 1);
  const int ball = mj_name2id(m.get(), mjOBJ_GEOM, "ball");
  const int crate = mj_name2id(m.get(), mjOBJ_GEOM, "crate");
  const int can = mj_name2id(m.get(), mjOBJ_GEOM, "can");
  ASSERT_GE(ball, 0);
  EXPECT_EQ(m->geom_type[ball], mjGEOM_SPHERE);
  EXPECT_EQ(m->geom_type[crate], mjGEOM_BOX);
  EXPECT_EQ(m->geom_type[can], mjGEOM_CYLINDER);
  EXPECT_DOUBLE_EQ(m->body_mass[m->geom_bodyid[ball]], 0.7);
  EXPECT_EQ(m->geom_friction[3 * crate], 0.3);
  // 17 digits: the compiled position is exactly the double given
  EXPECT_EQ(m->body_pos[3 * m->geom_bodyid[crate]], 0.1 + 0.2);
  const int x = mj_name2id(m.get(), mjOBJ_JOINT, "x");
  EXPECT_EQ(m->jnt_type[x], mjJNT_SLIDE);
  EXPECT_EQ(m->dof_damping[m->jnt_dofadr[x]], 1.5);
  const int yaw = mj_name2id(m.get(), mjOBJ_JOINT, "yaw");
  EXPECT_EQ(m->jnt_limited[yaw], 1);
  EXPECT_EQ(m->jnt_range[2 * yaw + 1], 1.0);
  EXPECT_EQ(m->actuator_gear[0], 2.0);
  EXPECT_EQ(m->actuator_ctrlrange[1], 3.0);
  EXPECT_EQ(m->actuator_trnid[0], x);
  EXPECT_EQ(m->site_pos[1], 0.2);
}

TEST(MjcfTest, LookAtFacesTheTarget) {
  const MjcfCamera c = MjcfCamera::LookAt("c", {0, -3, 2}, {0, 0, 0});
  // right = (1, 0, 0) (world +x to the image's right), up tilted toward +y
  EXPECT_NEAR(c.xyaxes[0], 1, 1e-12);
  EXPECT_NEAR(c.xyaxes[1], 0, 1e-12);
  EXPECT_GT(c.xyaxes[5], 0);  // image up has world +z
  EXPECT_GT(c.xyaxes[4], 0);
  // a compiled camera looks along -z of its frame: toward the target
  MjcfBuilder b("cam");
  b.worldbody().AddCamera(c);
  ModelPtr m = b.Build();
  DataPtr d = MakeData(m.get());
  mj_forward(m.get(), d.get());
  const double* r = d->cam_xmat;  // rows: x, y, z axes' components by column
  const double view[3] = {-r[2], -r[5], -r[8]};
  const double to_target[3] = {0, 3 / std::sqrt(13.0), -2 / std::sqrt(13.0)};
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(view[k], to_target[k], 1e-9);
  EXPECT_THROW(MjcfCamera::LookAt("down", {0, 0, 3}, {0, 0, 0}), Error);
}

TEST(MjcfTest, EscapesTextAndRefusesNonFiniteNumbers) {
  MjcfBuilder b("a<b>&\"c\"");
  const std::string xml = b.ToXml();
  EXPECT_NE(xml.find("model=\"a&lt;b&gt;&amp;&quot;c&quot;\""), std::string::npos) << xml;
  MjcfElement e("geom");
  EXPECT_THROW(e.Set("size", std::nan("")), Error);
  EXPECT_THROW(e.Set("pos", {0.0, INFINITY, 0.0}), Error);
  e.Set("size", 1.0).Set("size", 2.0);  // replaces
  EXPECT_EQ(e.Get("size"), std::optional<std::string>("2"));
  EXPECT_THROW(MjcfBuilder(""), Error);
}

TEST(MjcfTest, MujocoRejectionsBecomeMujocoErrors) {
  MjcfBuilder b("bad");
  b.AddMotor({.name = "m", .joint = "missing"});
  try {
    b.Build();
    FAIL() << "an actuator on a missing joint compiled";
  } catch (const MujocoError& e) {
    EXPECT_NE(std::string(e.what()).find("missing"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace manyworlds::sim
