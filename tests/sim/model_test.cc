#include "manyworlds/sim/model.h"

#include <cstdio>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "manyworlds/sim/ids.h"
#include "manyworlds/sim/mujoco_error.h"

namespace manyworlds::sim {
namespace {

constexpr char kBox[] = R"(
<mujoco model="box">
  <worldbody>
    <geom name="floor" type="plane" size="1 1 0.1"/>
    <body name="box" pos="0 0 0.1">
      <freejoint name="box_free"/>
      <geom name="box_geom" type="box" size="0.05 0.05 0.05"/>
      <site name="box_site"/>
    </body>
  </worldbody>
</mujoco>)";

TEST(ModelTest, LoadsFromStringAndOwnsMemory) {
  ModelPtr model = LoadModelFromString(kBox);
  ASSERT_NE(model, nullptr);
  EXPECT_EQ(model->nq, 7);
  DataPtr data = MakeData(model.get());
  ASSERT_NE(data, nullptr);
  mj_step(model.get(), data.get());
  // Moving transfers ownership; the deleters free exactly once (ASan-clean).
  ModelPtr moved = std::move(model);
  EXPECT_EQ(model, nullptr);
  EXPECT_NE(moved, nullptr);
}

TEST(ModelTest, BadXmlGivesErrorWithMujocoMessage) {
  try {
    LoadModelFromString("<mujoco><worldbody><geom type=\"box\"/></worldbody>", {}, "broken.xml");
    FAIL() << "expected MujocoError";
  } catch (const MujocoError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("broken.xml"), std::string::npos) << what;
    EXPECT_NE(what.find("XML"), std::string::npos) << what;  // MuJoCo's parser text
  }
}

TEST(ModelTest, CompileErrorIsReportedNotFatal) {
  // Unknown joint in an actuator: parses, fails in MuJoCo's compiler.
  const char* xml = R"(<mujoco><worldbody><body><joint name="j"/><geom size="0.1"/></body>
    </worldbody><actuator><motor joint="missing"/></actuator></mujoco>)";
  try {
    LoadModelFromString(xml);
    FAIL() << "expected MujocoError";
  } catch (const MujocoError& e) {
    EXPECT_NE(std::string(e.what()).find("missing"), std::string::npos) << e.what();
  }
}

TEST(ModelTest, IsAManyworldsError) {
  EXPECT_THROW(LoadModelFromString("not xml at all"), Error);
}

TEST(ModelTest, IncludesResolveFromVirtualFiles) {
  const char* main = R"(<mujoco model="main"><include file="part.xml"/></mujoco>)";
  const char* part = R"(<mujoco><worldbody><body name="included"><geom size="0.1"/></body>
    </worldbody></mujoco>)";
  const VirtualFile files[] = {{"part.xml", part}};
  ModelPtr model = LoadModelFromString(main, files, "main.xml");
  EXPECT_GE(mj_name2id(model.get(), mjOBJ_BODY, "included"), 0);
}

TEST(ModelTest, LoadsFromFileAndReportsMissingFile) {
  const std::string path = ::testing::TempDir() + "/manyworlds_box.xml";
  {
    std::ofstream out(path);
    out << kBox;
  }
  ModelPtr model = LoadModelFromFile(path);
  EXPECT_EQ(model->nbody, 2);
  std::remove(path.c_str());
  try {
    LoadModelFromFile(path);
    FAIL() << "expected MujocoError";
  } catch (const MujocoError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

TEST(ModelTest, MjuErrorThrowsInsteadOfExiting) {
  InstallMujocoHandlers();
  EXPECT_THROW(mju_error("deliberate failure"), MujocoError);
  try {
    mju_error("deliberate failure");
  } catch (const MujocoError& e) {
    EXPECT_NE(std::string(e.what()).find("deliberate failure"), std::string::npos);
  }
}

TEST(ModelTest, MakeDataRejectsNull) { EXPECT_THROW(MakeData(nullptr), MujocoError); }

TEST(IdLookupTest, FindsAndNamesMissingElements) {
  ModelPtr model = LoadModelFromString(kBox);
  IdLookup ids(model.get(), "box");
  EXPECT_EQ(ids.Body("box"), 1);
  EXPECT_GE(ids.Geom("box_geom"), 0);
  EXPECT_GE(ids.Site("box_site"), 0);
  EXPECT_EQ(ids.FreeJointQposAddress("box"), 0);
  EXPECT_EQ(ids.FindOptional(mjOBJ_BODY, "nope"), -1);
  try {
    ids.Site("gripper_site");
    FAIL() << "expected MujocoError";
  } catch (const MujocoError& e) {
    EXPECT_STREQ(e.what(), "model 'box' has no site named 'gripper_site'");
  }
  EXPECT_THROW(ids.MocapIndex("box"), MujocoError);
  EXPECT_THROW(ids.FreeJointQposAddress("world"), MujocoError);
}

}  // namespace
}  // namespace manyworlds::sim
