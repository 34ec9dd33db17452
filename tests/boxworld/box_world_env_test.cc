// The box world env: the env contract, determinism, task states, the
// observation layout (mask, hide_target), actuator scaling, model reuse, the
// study's rewards and ends on hand-driven episodes, crowded worlds and
// MuJoCo warnings.
#include "manyworlds/boxworld/box_world_env.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include "manyworlds/boxworld/boxworld.h"
#include "manyworlds/boxworld/world_model.h"
#include "manyworlds/core/env_checker.h"
#include "manyworlds/core/error.h"
#include "manyworlds/core/policy.h"
#include "manyworlds/core/registry.h"
#include "manyworlds/core/wrapper.h"
#include "manyworlds/core/wrappers/time_limit.h"
#include "manyworlds/sim/scene_source.h"
#include "tests/support/scratch_dir.h"

namespace manyworlds::boxworld {
namespace {

BoxWorldEnv::Config Simple() { return {}; }
BoxWorldEnv::Config Complex() {
  BoxWorldEnv::Config c;
  c.task = BoxTask::kComplex;
  return c;
}

float Info(const StepResult& r, const char* name) { return r.info.Get(name); }

void SetWorld(Env& env, const WorldParams& w) { env.SetTaskState(TaskState{env.id(), ToJson(w)}); }

// The agent alone, on the x axis, 2.5 m from the target.
WorldParams Corridor() {
  WorldParams w;
  w.agent_start = {-1.5, 0.0};
  w.target = {1.0, 0.0};
  return w;
}

double AgentX(const BoxWorldEnv& env) { return env.data()->qpos[0]; }

TEST(BoxWorldEnvTest, BothTasksPassTheEnvChecker) {
  for (auto config : {Simple(), Complex()}) {
    config.distribution.num_boxes = {1, 3};
    config.distribution.box_shapes = {Shape::kBox, Shape::kCylinder, Shape::kSphere};
    const CheckReport report = CheckEnv([&] { return std::make_unique<BoxWorldEnv>(config); });
    EXPECT_TRUE(report.ok()) << report.ToString();
  }
}

TEST(BoxWorldEnvTest, SameTaskSeedGivesTheSameWorldAndTrajectory) {
  auto run = [](uint64_t task_seed) {
    BoxWorldEnv::Config c = Complex();
    c.distribution.num_boxes = {2, 4};
    c.distribution.box_shapes = {Shape::kBox, Shape::kSphere};
    BoxWorldEnv env(c);
    env.SeedTask(task_seed);
    env.ResetTaskState();
    std::vector<float> trace = env.Reset().env_obs;
    Rng rng(5);
    for (int t = 0; t < 200; ++t) {
      const float a[3] = {static_cast<float>(rng.Uniform(-1, 1)),
                          static_cast<float>(rng.Uniform(-1, 1)),
                          static_cast<float>(rng.Uniform(-1, 1))};
      const StepResult r = env.Step(a);
      trace.insert(trace.end(), r.obs.env_obs.begin(), r.obs.env_obs.end());
      trace.push_back(r.reward);
    }
    return std::make_pair(env.GetTaskState().Dump(), trace);
  };
  const auto a = run(3);
  const auto b = run(3);
  EXPECT_EQ(a.first, b.first);
  EXPECT_EQ(a.second, b.second);  // bitwise
  EXPECT_NE(a.first, run(4).first);
}

TEST(BoxWorldEnvTest, TaskStatesRoundTripAndBadOnesAreRejectedKeepingTheTask) {
  BoxWorldEnv env(Complex());
  env.SeedTask(1);
  env.ResetTaskState();
  const TaskState state = env.GetTaskState();
  BoxWorldEnv other(Complex());
  other.SetTaskState(TaskState::Parse(state.Dump()));
  EXPECT_EQ(other.GetTaskState(), state);
  EXPECT_EQ(other.world(), env.world());

  auto rejects = [&](const TaskState& bad, const std::string& fragment) {
    try {
      env.SetTaskState(bad);
      ADD_FAILURE() << "accepted " << bad.Dump();
    } catch (const TaskStateError& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
    EXPECT_EQ(env.GetTaskState(), state);  // the previous task stays
  };
  rejects(TaskState{"box-world-simple", state.params}, "box-world-simple");
  TaskState missing = state;
  missing.params.erase("target");
  rejects(missing, "target is missing");
  TaskState negative = state;
  negative.params["boxes"][0]["size"] = -1.0;
  rejects(negative, "boxes[0].size must be in [0.01, 1.25]");
  TaskState overlap = state;
  overlap.params["boxes"][0]["start"] = overlap.params["agent_start"];
  rejects(overlap, "boxes[0].start must be at least");
  WorldParams near = Corridor();
  near.target = {-1.0, 0.0};  // 0.5 m from the agent
  rejects(TaskState{env.id(), ToJson(near)},
          "target must be at least min_target_distance = 1 m from agent_start, got 0.5 m");
  TaskState none = state;
  none.params["boxes"] = nlohmann::json::array();
  rejects(none, "the complex task needs at least one box");
  WorldParams crowded = env.world();
  BoxParams tiny;
  tiny.size = 0.02;
  crowded.boxes.clear();
  for (int i = 0; i < 9; ++i) {
    tiny.start = {-2.0 + 0.3 * i, -2.2};
    crowded.boxes.push_back(tiny);
  }
  crowded.agent_start = {0, 1};
  crowded.target = {0, -0.5};
  ASSERT_NO_THROW(Validate(crowded));
  rejects(TaskState{env.id(), ToJson(crowded)}, "max_boxes = 8");
}

TEST(BoxWorldEnvTest, ObservationHasMaskedBoxSlotsAndTheTargetUnlessHidden) {
  WorldParams w = Corridor();
  BoxParams a, b;
  a.start = {0.0, 1.5};
  a.start_yaw = 0.5;
  b.shape = Shape::kSphere;
  b.size = 0.2;
  b.start = {-1.0, -1.5};
  w.boxes = {a, b};
  for (bool hide : {false, true}) {
    BoxWorldEnv::Config c = Simple();
    c.max_boxes = 4;
    c.hide_target = hide;
    BoxWorldEnv env(c);
    ASSERT_EQ(env.spec().env_obs_space.flat_size(), 8 + 9 * 4);
    SetWorld(env, w);
    const Observation obs = env.Reset();
    const std::vector<float>& o = obs.env_obs;
    EXPECT_FLOAT_EQ(o[0], 5.0f);
    EXPECT_FLOAT_EQ(o[1], -1.5f);
    EXPECT_FLOAT_EQ(o[2], 0.0f);
    EXPECT_FLOAT_EQ(o[3], 1.0f);  // cos of heading 0
    // slot 0: box a
    EXPECT_EQ(o[8], 1.0f);
    EXPECT_FLOAT_EQ(o[9], 0.0f);
    EXPECT_FLOAT_EQ(o[10], 1.5f);
    EXPECT_FLOAT_EQ(o[11], 0.125f);
    EXPECT_FLOAT_EQ(o[12], static_cast<float>(std::cos(0.25)));  // quaternion w
    EXPECT_FLOAT_EQ(o[15], static_cast<float>(std::sin(0.25)));  // quaternion z
    EXPECT_EQ(o[16], 0.0f);
    // slot 1: box b
    EXPECT_EQ(o[17], 1.0f);
    EXPECT_FLOAT_EQ(o[18], -1.0f);
    EXPECT_FLOAT_EQ(o[20], 0.2f);
    // slots 2 and 3: absent, all zero
    for (size_t i = 8 + 9 * 2; i < o.size(); ++i) EXPECT_EQ(o[i], 0.0f) << i;
    if (hide) {
      EXPECT_EQ(obs.task_obs, (std::vector<float>{0.0f, 0.0f}));
    } else {
      EXPECT_EQ(obs.task_obs, (std::vector<float>{1.0f, 0.0f}));
    }
  }
}

TEST(BoxWorldEnvTest, ActionsAreScaledToTheActuatorRanges) {
  WorldParams w = Corridor();
  w.agent_force = 8.0;
  w.agent_torque = 0.25;
  BoxWorldEnv env(Simple());
  SetWorld(env, w);
  env.Reset();
  const float a[3] = {0.5f, -0.25f, 1.0f};
  env.Step(a);
  EXPECT_DOUBLE_EQ(env.data()->ctrl[0], 4.0);
  EXPECT_DOUBLE_EQ(env.data()->ctrl[1], -2.0);
  EXPECT_DOUBLE_EQ(env.data()->ctrl[2], 0.25);
  const float beyond[3] = {3.0f, -2.0f, 0.0f};  // clipped to [-1, 1] first
  env.Step(beyond);
  EXPECT_DOUBLE_EQ(env.data()->ctrl[0], 8.0);
  EXPECT_DOUBLE_EQ(env.data()->ctrl[1], -8.0);
  EXPECT_EQ(env.model()->actuator_ctrlrange[1], 8.0);
  EXPECT_EQ(env.model()->actuator_ctrlrange[5], 0.25);
  // the force moves the agent: top speed agent_force / 2.5 m/s, reached
  // with a time constant of 1 kg / 2.5 N s/m = 0.4 s
  w.agent_force = 2.5;
  SetWorld(env, w);
  env.Reset();
  for (int t = 0; t < 80; ++t) {  // 2 s
    const float down[3] = {0.0f, -1.0f, 0.0f};
    env.Step(down);
  }
  EXPECT_NEAR(env.data()->qvel[1], -2.5 / kAgentDamping, 0.02);
}

// The smallest agent and box at the largest force and torque, driven into
// each wall and corner while spinning against the box.
WorldParams Violent() {
  WorldParams w = Corridor();
  w.agent_radius = kMinObjectSize;
  w.agent_force = kMaxAgentForce;
  w.agent_torque = kMaxAgentTorque;
  BoxParams box;
  box.size = kMinObjectSize;
  box.start = {w.agent_start[0] + 0.05, 0.0};
  w.boxes = {box};
  return w;
}

TEST(BoxWorldEnvTest, TheAgentCannotLeaveTheArenaAndABoxThatDoesIsReported) {
  // Before the agent's joints were limited, a 0.01 m agent at 30 N (top
  // speed 12 m/s) driven into a wall passed through it; nothing reported it.
  const WorldParams w = Violent();
  BoxWorldEnv env(Complex());
  SetWorld(env, w);
  const double reach = w.floor_size / 2 - w.agent_radius;
  double farthest = 0;
  int steps = 0, reported = 0;
  const float pushes[][3] = {{1, 0, 1},  {-1, 0, -1}, {0, 1, 1},  {0, -1, 1},
                             {1, 1, -1}, {-1, -1, 1}, {1, -1, 1}, {-1, 1, -1}};
  for (const auto& a : pushes) {
    env.Reset();
    for (int t = 0; t < 300; ++t) {
      const float spin[3] = {a[0], a[1], t % 40 < 20 ? a[2] : -a[2]};
      const StepResult r = env.Step(spin);
      ++steps;
      const double* q = env.data()->qpos;  // agent x, y, yaw; the box's free joint
      farthest = std::max({farthest, std::abs(q[0]), std::abs(q[1])});
      const bool box_outside = std::abs(q[3]) > w.floor_size / 2 + kWallThickness ||
                               std::abs(q[4]) > w.floor_size / 2 + kWallThickness;
      // a box outside the walls is never silent
      if (box_outside) ASSERT_GT(Info(r, "sim_warnings"), 0.0f) << t;
      if (Info(r, "sim_warnings") > 0) {
        ++reported;
        EXPECT_TRUE(r.truncated);
        EXPECT_EQ(r.reward, 0.0f);
      }
      if (r.terminated || r.truncated) env.Reset();
    }
  }
  // the joint limit is soft: the agent may press into the wall, never past it
  EXPECT_LE(farthest, w.floor_size / 2 + kWallThickness);
  EXPECT_GT(farthest, reach - 0.05);  // it did reach the walls
  EXPECT_LT(reported, steps);
}

TEST(BoxWorldEnvTest, ABoxOutsideTheWallsEndsTheEpisodeOrThrows) {
  for (bool throw_on_warning : {false, true}) {
    BoxWorldEnv::Config c = Complex();
    c.throw_on_sim_warning = throw_on_warning;
    BoxWorldEnv env(c);
    WorldParams w = Corridor();
    w.boxes = {BoxParams{.start = {0.0, 1.0}}};
    SetWorld(env, w);
    env.Reset();
    // as if a hit had sent it through the +y wall
    const_cast<mjData*>(env.data())->qpos[4] = w.floor_size / 2 + 0.5;
    const float still[3] = {0, 0, 0};
    if (throw_on_warning) {
      try {
        env.Step(still);
        ADD_FAILURE() << "no throw";
      } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("box-world-complex: 1 box(es) left the arena (box 0"),
                  std::string::npos)
            << e.what();
      }
    } else {
      const StepResult r = env.Step(still);
      EXPECT_EQ(Info(r, "sim_warnings"), 1.0f);
      EXPECT_TRUE(r.truncated);
      EXPECT_FALSE(r.terminated);
      EXPECT_EQ(r.reward, 0.0f);
    }
    // a reset puts the box back
    env.Reset();
    EXPECT_EQ(Info(env.Step(still), "sim_warnings"), 0.0f);
  }
}

TEST(BoxWorldEnvTest, SimpleTaskPaysDistanceThenOneHundredOnceAndTerminates) {
  BoxWorldEnv env(Simple());
  SetWorld(env, Corridor());
  env.Reset();
  const float forward[3] = {1.0f, 0.0f, 0.0f};
  int steps = 0, bonuses = 0;
  StepResult r;
  do {
    r = env.Step(forward);
    ++steps;
    const double d = std::abs(1.0 - AgentX(env));
    if (d < 1.0) {
      EXPECT_EQ(r.reward, 100.0f);
      ++bonuses;
    } else {
      ASSERT_FLOAT_EQ(r.reward, static_cast<float>(-0.001 * d)) << steps;
      ASSERT_FLOAT_EQ(Info(r, "distance"), static_cast<float>(d));
      ASSERT_FALSE(r.terminated);
      ASSERT_EQ(Info(r, "success"), 0.0f);
    }
  } while (!r.terminated && !r.truncated);
  EXPECT_EQ(bonuses, 1);
  EXPECT_TRUE(r.terminated);
  EXPECT_FALSE(r.truncated);
  EXPECT_EQ(Info(r, "success"), 1.0f);
  EXPECT_LT(steps, 100);  // 1.5 m at up to 2 m/s, 0.025 s per step
  EXPECT_THROW(env.Step(forward), EpisodeStateError);
}

TEST(BoxWorldEnvTest, EpisodesAreTruncatedAt1024Steps) {
  BoxWorldEnv env(Simple());
  SetWorld(env, Corridor());
  env.Reset();
  const float still[3] = {0.0f, 0.0f, 0.0f};
  StepResult r;
  for (int t = 0; t < 1024; ++t) {
    r = env.Step(still);
    ASSERT_EQ(r.truncated, t == 1023) << t;
    ASSERT_FALSE(r.terminated);
    ASSERT_FLOAT_EQ(r.reward, -0.0025f);
  }
  EXPECT_EQ(env.spec().max_episode_steps, 1024);
}

TEST(BoxWorldEnvTest, DeliveringOneOfTwoBoxesPaysOneHundredAndDropsItFromTheSum) {
  // box 0 sits 1.05 m from the target, between the agent and the target;
  // box 1 is far away and never touched
  WorldParams w = Corridor();
  w.agent_start = {-0.35, 0.0};
  w.target = {1.3, 0.0};
  BoxParams near, far;
  near.start = {0.25, 0.0};
  far.start = {-1.5, 1.8};
  w.boxes = {near, far};
  BoxWorldEnv env(Complex());
  SetWorld(env, w);
  env.Reset();
  const double d_far = std::hypot(1.3 - -1.5, 1.8);
  const float forward[3] = {0.6f, 0.0f, 0.0f};
  StepResult r;
  int delivered_at = -1;
  for (int t = 0; t < 200; ++t) {
    r = env.Step(forward);
    const int q0 = env.model()->jnt_qposadr[3];  // joints: agent x, y, yaw, box0, box1
    const double d_near = std::hypot(env.data()->qpos[q0] - 1.3, env.data()->qpos[q0 + 1]);
    if (delivered_at < 0 && d_near < 1.0) {
      delivered_at = t;
      EXPECT_NEAR(r.reward, 100.0 - 0.001 * d_far, 1e-4);
      EXPECT_EQ(Info(r, "boxes_delivered"), 1.0f);
      EXPECT_FALSE(r.terminated);
      EXPECT_EQ(Info(r, "success"), 0.0f);
      EXPECT_TRUE(env.delivered(0));
      EXPECT_EQ(r.obs.env_obs[8 + 8], 1.0f);  // slot 0's delivered flag
    } else if (delivered_at < 0) {
      ASSERT_NEAR(r.reward, -0.001 * (d_near + d_far), 1e-5) << t;
      ASSERT_EQ(Info(r, "boxes_delivered"), 0.0f);
    } else {
      // box 0 left the sum for good, wherever it slides now
      ASSERT_NEAR(r.reward, -0.001 * d_far, 1e-5) << t;
      ASSERT_NEAR(Info(r, "distance"), d_far, 1e-4);
      ASSERT_EQ(Info(r, "boxes_delivered"), 1.0f);
    }
    if (delivered_at >= 0 && t > delivered_at + 20) break;
  }
  EXPECT_GT(delivered_at, 0);
  EXPECT_FALSE(env.delivered(1));
}

TEST(BoxWorldEnvTest, ComplexTaskTerminatesWhenEveryBoxIsDelivered) {
  WorldParams w = Corridor();
  w.agent_start = {-0.35, 0.0};
  w.target = {1.3, 0.0};
  BoxParams near;
  near.start = {0.25, 0.0};
  w.boxes = {near};
  BoxWorldEnv env(Complex());
  SetWorld(env, w);
  env.Reset();
  const float forward[3] = {0.6f, 0.0f, 0.0f};
  StepResult r;
  int t = 0;
  do {
    r = env.Step(forward);
  } while (!r.terminated && ++t < 200);
  EXPECT_TRUE(r.terminated);
  EXPECT_EQ(Info(r, "success"), 1.0f);
  EXPECT_NEAR(r.reward, 100.0, 1e-6);
}

TEST(BoxWorldEnvTest, AModelIsBuiltOnlyWhenTheWorldStructureChanges) {
  BoxWorldEnv::Config fixed = Complex();
  fixed.distribution.layout_seed = 4;
  BoxWorldEnv env(fixed);
  env.SeedTask(0);
  std::vector<double> targets;
  for (int i = 0; i < 5; ++i) {
    env.ResetTaskState();
    env.Reset();
    targets.push_back(env.world().target[0]);
    const int site = mj_name2id(env.model(), mjOBJ_SITE, "target");
    EXPECT_EQ(env.data()->site_xpos[3 * site], env.world().target[0]);
  }
  EXPECT_EQ(env.models_built(), 1);
  EXPECT_NE(targets[0], targets[1]);
  for (const char* camera : {"top", "perspective", "front"}) {
    EXPECT_GE(mj_name2id(env.model(), mjOBJ_CAMERA, camera), 0) << camera;
  }

  BoxWorldEnv::Config broad = Complex();
  broad.distribution.floor_size = {4, 6};
  BoxWorldEnv varied(broad);
  for (int i = 0; i < 5; ++i) varied.ResetTaskState();
  EXPECT_EQ(varied.models_built(), 5);
}

TEST(BoxWorldEnvTest, TheScriptedPolicyReachesTargetsAndPushesBoxes) {
  for (const BoxTask task : {BoxTask::kSimple, BoxTask::kComplex}) {
    BoxWorldEnv::Config c;
    c.task = task;
    BoxWorldEnv env(c);
    env.SeedTask(1);
    std::unique_ptr<Policy> policy = env.CreateScriptedPolicy();
    ASSERT_NE(policy, nullptr);
    int successes = 0;
    constexpr int kEpisodes = 10;
    for (int e = 0; e < kEpisodes; ++e) {
      env.ResetTaskState();
      Observation obs = env.Reset();
      std::vector<float> action(3);
      StepResult r;
      do {
        policy->Act(obs.env_obs, obs.task_obs, action);
        r = env.Step(action);
        obs = r.obs;
      } while (!r.terminated && !r.truncated);
      successes += Info(r, "success") > 0;
    }
    if (task == BoxTask::kSimple) {
      EXPECT_EQ(successes, kEpisodes);
    } else {
      EXPECT_GE(successes, kEpisodes / 2);
    }
  }
}

// The MuJoCo scene and scripted policy capabilities are found behind
// wrappers; the scene is the current world's, and its MJCF is WorldMjcf's.
TEST(BoxWorldEnvTest, TheSceneAndScriptedPolicyAreFoundBehindWrappers) {
  TimeLimit wrapped(std::make_unique<BoxWorldEnv>(Simple()), 50);
  const auto& env = dynamic_cast<const BoxWorldEnv&>(wrapped.inner());
  const auto* scene = FindThroughWrappers<sim::SceneSource>(wrapped);
  ASSERT_EQ(scene, &env);
  EXPECT_EQ(FindThroughWrappers<ScriptedPolicySource>(wrapped), &env);
  // no world, no scene
  EXPECT_EQ(scene->ActiveScene().model, nullptr);
  const std::filesystem::path dir = test_support::ScratchDir("box_world_env", "scene", true);
  EXPECT_THROW(scene->SaveSceneXml((dir / "none.xml").string()), EpisodeStateError);
  wrapped.SeedTask(3);
  wrapped.ResetTaskState();
  EXPECT_EQ(scene->ActiveScene().model, env.model());
  EXPECT_EQ(scene->ActiveScene().data, env.data());
  EXPECT_EQ(scene->default_camera(), "front");
  scene->SaveSceneXml((dir / "world.xml").string());
  std::ifstream in(dir / "world.xml");
  const std::string xml((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(xml, WorldMjcf(env.world()).ToXml());
}

// 64 cubes of 10 cm (the most a world holds) in an 8 x 8 grid on a 6 m
// floor; the agent and the target in the corners.
WorldParams SixtyFourBoxes() {
  WorldParams w;
  w.floor_size = 6.0;
  w.success_radius = 0.3;
  w.min_target_distance = 0.5;
  w.agent_start = {-2.6, -2.6};
  w.target = {2.6, 2.6};
  BoxParams box;
  box.size = 0.1;
  for (int i = 0; i < 64; ++i) {
    box.start = {-1.75 + 0.5 * (i % 8), -1.75 + 0.5 * (i / 8)};
    w.boxes.push_back(box);
  }
  return w;
}

BoxWorldEnv::Config SixtyFourSlots(bool throw_on_sim_warning = false) {
  BoxWorldEnv::Config c = Complex();
  c.max_boxes = 64;
  c.throw_on_sim_warning = throw_on_sim_warning;
  return c;
}

TEST(BoxWorldEnvTest, SixtyFourBoxesFitTheContactList) {
  // MuJoCo 2.2.2's default list (100 contacts) held about 25 resting boxes
  // (4 floor contacts each): every step of a world with more raised
  // CONTACTFULL and ended the episode at once.
  const WorldParams world = SixtyFourBoxes();
  BoxWorldEnv env(SixtyFourSlots());
  SetWorld(env, world);
  EXPECT_EQ(env.model()->nconmax, ContactCapacity(world));
  EXPECT_EQ(env.model()->njmax, ConstraintCapacity(world));
  env.Reset();
  const float push[3] = {1.0f, 1.0f, 0.0f};  // into the grid
  for (int t = 0; t < 100; ++t) {
    const StepResult r = env.Step(push);
    ASSERT_EQ(Info(r, "sim_warnings"), 0.0f) << "step " << t;
    ASSERT_FALSE(r.truncated) << "step " << t;
    ASSERT_LT(r.reward, 0.0f) << "step " << t;
  }
  EXPECT_GT(env.data()->ncon, 4 * 25);  // more than the default list holds

  // the one-box worlds keep MuJoCo's defaults (and their memory)
  BoxWorldEnv one(Complex());
  one.ResetTaskState();
  EXPECT_EQ(one.model()->nconmax, 100);
  EXPECT_EQ(one.model()->njmax, 500);
}

// A valid world no longer fills its contact list, so the warning is made as
// every world of 26 or more boxes met it before ContactCapacity: the env's
// compiled model cut back to MuJoCo's default list of 100 contacts (MuJoCo
// reads mjModel::nconmax at each collision pass). Returns the old size.
int ShrinkContactList(const BoxWorldEnv& env) {
  mjModel* model = const_cast<mjModel*>(env.model());
  const int old = model->nconmax;
  model->nconmax = 100;
  return old;
}

TEST(BoxWorldEnvTest, AMujocoWarningEndsTheEpisodeWithoutRewardAndTheNextResetIsClean) {
  BoxWorldEnv env(SixtyFourSlots());
  SetWorld(env, SixtyFourBoxes());
  const Observation fresh = env.Reset();
  const float still[3] = {0.0f, 0.0f, 0.0f};
  const StepResult clean = env.Step(still);  // the same step, warning-free
  ASSERT_EQ(Info(clean, "sim_warnings"), 0.0f);

  const int capacity = ShrinkContactList(env);
  env.Reset();
  const StepResult r = env.Step(still);
  EXPECT_TRUE(r.truncated);
  EXPECT_FALSE(r.terminated);
  EXPECT_EQ(r.reward, 0.0f);
  EXPECT_GE(Info(r, "sim_warnings"), 1.0f);  // every CONTACTFULL of the step's 5 substeps
  EXPECT_EQ(Info(r, "success"), 0.0f);
  for (float v : r.obs.env_obs) ASSERT_TRUE(std::isfinite(v));

  // the list back to its size: the next episode starts as a fresh one, with
  // no warning carried over
  const_cast<mjModel*>(env.model())->nconmax = capacity;
  EXPECT_EQ(env.Reset().env_obs, fresh.env_obs);
  const StepResult after = env.Step(still);
  EXPECT_EQ(Info(after, "sim_warnings"), 0.0f);
  EXPECT_FALSE(after.truncated);
  EXPECT_EQ(after.reward, clean.reward);
  EXPECT_EQ(after.obs.env_obs, clean.obs.env_obs);
}

TEST(BoxWorldEnvTest, ThrowOnSimWarningThrowsNamingTheWarning) {
  BoxWorldEnv env(SixtyFourSlots(/*throw_on_sim_warning=*/true));
  SetWorld(env, SixtyFourBoxes());
  const int capacity = ShrinkContactList(env);
  env.Reset();
  const float still[3] = {0.0f, 0.0f, 0.0f};
  std::string message;
  try {
    env.Step(still);
  } catch (const Error& e) {
    message = e.what();
  }
  EXPECT_NE(message.find("box-world-complex"), std::string::npos) << message;
  EXPECT_NE(message.find("CONTACTFULL"), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;

  const_cast<mjModel*>(env.model())->nconmax = capacity;
  env.Reset();
  const StepResult r = env.Step(still);
  EXPECT_EQ(Info(r, "sim_warnings"), 0.0f);
  EXPECT_FALSE(r.truncated);
}

TEST(BoxWorldEnvTest, RegistryOptionsReachTheGeneratorAndBadOnesAreErrors) {
  Registry registry;
  RegisterBoxWorldSuite(registry);
  EXPECT_TRUE(registry.Contains("box-world-simple"));
  EXPECT_TRUE(registry.Contains("box-world-complex"));
  auto env = registry.Make("box-world-complex", {{"floor_size", 6.0},
                                                 {"floor_size_max", 8.0},
                                                 {"num_boxes", 2},
                                                 {"num_boxes_max", 3},
                                                 {"box_shapes", "sphere, cylinder"},
                                                 {"max_boxes", 3}});
  for (int i = 0; i < 20; ++i) {
    env->ResetTaskState();
    const nlohmann::json p = env->GetTaskState().params;
    ASSERT_GE(p["floor_size"].get<double>(), 6.0);
    ASSERT_LE(p["floor_size"].get<double>(), 8.0);
    ASSERT_GE(p["boxes"].size(), 2u);
    ASSERT_LE(p["boxes"].size(), 3u);
    for (const auto& box : p["boxes"]) ASSERT_NE(box["shape"], "box");
  }
  EXPECT_EQ(env->spec().env_obs_space.flat_size(), 8 + 9 * 3);

  auto error = [&](const char* id, const nlohmann::json& options) -> std::string {
    try {
      registry.Make(id, options);
    } catch (const ConfigError& e) {
      return e.what();
    }
    return "(accepted)";
  };
  EXPECT_EQ(error("box-world-simple", {{"num_boxes", 40}, {"box_size", 0.4}}),
            "env 'box-world-simple': box world: num_boxes must be in [0, 9] on a 5 m floor with "
            "boxes of footprint radius up to 0.565685 m (their footprints may cover at most 50% "
            "of the floor), got 40");
  EXPECT_EQ(error("box-world-simple", {{"box_size", -0.1}}),
            "env 'box-world-simple': box world: box_size (min) must be in [0.01, 1.25] (up to "
            "floor_size / 4), got -0.1");
  EXPECT_EQ(error("box-world-simple", {{"floor_size", 1.0}, {"min_target_distance_ratio", 0.5}}),
            "env 'box-world-simple': box world: min_target_distance_ratio must be in [0.2, "
            "0.424264] (success_radius_ratio to (1 - 2 success_radius_ratio) / sqrt(2)), got 0.5");
  EXPECT_NE(error("box-world-simple", {{"box_shapes", "cube"}}).find("'box_shapes'"),
            std::string::npos);
  EXPECT_EQ(error("box-world-simple", {{"num_boxes", 9}}),
            "env 'box-world-simple': options 'num_boxes' and 'num_boxes_max' must be at most "
            "max_boxes = 8 (the observation's box slots), got up to 9 boxes; raise max_boxes (up "
            "to 64) or lower num_boxes");
  EXPECT_NE(error("box-world-complex", {{"num_boxes", 0}}).find("for the complex task"),
            std::string::npos);
  EXPECT_NE(error("box-world-simple", {{"floor_size", "nan"}}).find("floor_size"),
            std::string::npos);
  EXPECT_NO_THROW(registry.Make("box-world-simple", {{"num_boxes", 0}}));
  // valid ranges that leave no room for the target fail at construction
  EXPECT_NE(error("box-world-complex",
                  {{"num_boxes", 12}, {"max_boxes", 12}, {"min_target_distance_ratio", 0.4}})
                .find("could not place the target"),
            std::string::npos);
}

}  // namespace
}  // namespace manyworlds::boxworld
