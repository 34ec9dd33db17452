#include "manyworlds/sim/state.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "manyworlds/sim/model.h"
#include "manyworlds/sim/mujoco_error.h"
#include "manyworlds/sim/warnings.h"

namespace manyworlds::sim {
namespace {

constexpr char kPendulumAndBox[] = R"(
<mujoco>
  <option timestep="0.002"/>
  <worldbody>
    <geom type="plane" size="1 1 0.1"/>
    <body name="mocap" mocap="true" pos="0.3 0 0.5"/>
    <body pos="0 0 1">
      <joint name="hinge" type="hinge" axis="0 1 0" damping="0.1"/>
      <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.02"/>
    </body>
    <body pos="0.5 0 0.2">
      <freejoint/>
      <geom type="box" size="0.05 0.05 0.05"/>
    </body>
  </worldbody>
  <actuator><motor joint="hinge"/></actuator>
</mujoco>)";

class StateTest : public ::testing::Test {
 protected:
  void SetUp() override {
    model_ = LoadModelFromString(kPendulumAndBox);
    data_ = MakeData(model_.get());
  }
  void TearDown() override {
    // Every test here must leave the simulation warning-free.
    EXPECT_EQ(WarningTotal(data_.get()), 0) << DescribeWarnings(data_.get());
  }
  ModelPtr model_;
  DataPtr data_;
};

TEST_F(StateTest, RestoredStateReplaysBitIdentically) {
  const mjModel* m = model_.get();
  mjData* d = data_.get();
  for (int i = 0; i < 100; ++i) mj_step(m, d);
  d->ctrl[0] = 0.3;
  d->mocap_pos[2] = 0.7;
  const SimState snapshot = GetState(m, d);
  for (int i = 0; i < 200; ++i) mj_step(m, d);
  const SimState first = GetState(m, d);

  mj_resetData(m, d);
  SetState(m, d, snapshot);
  for (int i = 0; i < 200; ++i) mj_step(m, d);
  EXPECT_EQ(GetState(m, d), first);
  EXPECT_EQ(MaxAbsDifference(GetState(m, d), first), 0.0);
}

TEST_F(StateTest, GetStateReusesBuffersAndSetStateChecksSizes) {
  SimState state;
  GetState(model_.get(), data_.get(), &state);
  EXPECT_EQ(state.qpos.size(), static_cast<size_t>(model_->nq));
  EXPECT_EQ(state.mocap_pos.size(), 3u);
  state.qvel.pop_back();
  EXPECT_THROW(SetState(model_.get(), data_.get(), state), MujocoError);
  SimState other = GetState(model_.get(), data_.get());
  EXPECT_EQ(MaxAbsDifference(state, other), std::numeric_limits<double>::infinity());
}

TEST(WarningsTest, BadStateIsCountedAndThrown) {
  ModelPtr model = LoadModelFromString(kPendulumAndBox);
  DataPtr data = MakeData(model.get());
  data->qpos[0] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(StepAndCheck(model.get(), data.get(), 1, false), 1);
  EXPECT_EQ(WarningTotal(data.get()), 1);
  EXPECT_NE(DescribeWarnings(data.get()).find("BADQPOS"), std::string::npos)
      << DescribeWarnings(data.get());
  EXPECT_THROW(ThrowIfWarnings(data.get(), "test"), SimulationWarningError);
  ClearWarnings(data.get());
  EXPECT_EQ(WarningTotal(data.get()), 0);
  EXPECT_NO_THROW(ThrowIfWarnings(data.get(), "test"));

  data->qvel[0] = std::numeric_limits<double>::infinity();
  EXPECT_THROW(StepAndCheck(model.get(), data.get(), 1, true, "ctx"), SimulationWarningError);
}

}  // namespace
}  // namespace manyworlds::sim
