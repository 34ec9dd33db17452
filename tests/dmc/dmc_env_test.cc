// The dm_control-style envs: the env contract on every id, spaces, control timesteps and
// episode length, dm_control's initial states, the observation layout, the reward read from
// the simulator, and the HiP-BMDP variants (task states, MTRL's split, the physics each
// variant changes, the shared model cache).
#ifdef MANYWORLDS_DMC_HAS_ENVS

#include "manyworlds/dmc/dmc_env.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "manyworlds/core/env_checker.h"
#include "manyworlds/core/error.h"
#include "manyworlds/core/registry.h"
#include "manyworlds/core/rng.h"
#include "manyworlds/dmc/dmc.h"
#include "manyworlds/dmc/rewards.h"

namespace manyworlds::dmc {
namespace {

const std::vector<std::string> kIds = {"dmc-finger-spin",
                                       "dmc-cheetah-run",
                                       "dmc-walker-walk",
                                       "hipbmdp-finger-spin-size",
                                       "hipbmdp-cheetah-run-torso-length",
                                       "hipbmdp-walker-walk-friction",
                                       "hipbmdp-walker-walk-foot-length"};

const Registry& DmcRegistry() {
  static const Registry registry = [] {
    Registry r;
    RegisterDmcSuite(r);
    return r;
  }();
  return registry;
}

DmcEnv::Config Single(DmcTask task) { return {.task = task}; }
DmcEnv::Config Multi(Variation variation) {
  return {.task = TaskOf(variation), .variation = variation};
}

std::vector<float> RandomAction(Rng& rng, int64_t size) {
  std::vector<float> action(size);
  for (float& a : action) a = static_cast<float>(rng.Uniform(-1.0, 1.0));
  return action;
}

float Info(const StepResult& r, const char* name) {
  for (size_t i = 0; i < r.info.names.size(); ++i) {
    if (r.info.names[i] == name) return r.info.values[i];
  }
  ADD_FAILURE() << "no info field " << name;
  return NAN;
}

TEST(DmcSuiteTest, RegistersTheSevenIdsInFamilyDmc) {
  ASSERT_EQ(DmcRegistry().Ids(), kIds);
  for (const auto& entry : DmcRegistry().entries()) EXPECT_EQ(entry.family, "dmc");
}

TEST(DmcSuiteTest, CheckEnvPassesOnEveryId) {
  for (const std::string& id : kIds) {
    SCOPED_TRACE(id);
    const CheckReport report = CheckEnv([&] { return DmcRegistry().Make(id); });
    EXPECT_TRUE(report.ok()) << report.ToString();
  }
}

TEST(DmcSuiteTest, SplitIsAnOptionOfTheFingerSizeEnvOnly) {
  EXPECT_NO_THROW(DmcRegistry().Make("hipbmdp-finger-spin-size", {{"split", "mtrl"}}));
  EXPECT_THROW(DmcRegistry().Make("hipbmdp-finger-spin-size", {{"split", "train"}}), ConfigError);
  EXPECT_THROW(DmcRegistry().Make("hipbmdp-walker-walk-friction", {{"split", "mtrl"}}),
               ConfigError);
  EXPECT_THROW(DmcEnv({.task = DmcTask::kCheetahRun,
                       .variation = Variation::kCheetahTorsoLength,
                       .split = Split::kMtrl}),
               ConfigError);
  EXPECT_THROW(DmcEnv({.task = DmcTask::kFingerSpin, .variation = Variation::kWalkerFriction}),
               ConfigError);
}

struct Expected {
  DmcTask task;
  int obs, action;
  double control_dt;
};

TEST(DmcEnvTest, SpacesControlTimestepsAndEpisodeLengthAreDmControls) {
  for (const Expected& e :
       {Expected{DmcTask::kFingerSpin, 9, 2, 0.02}, Expected{DmcTask::kCheetahRun, 17, 6, 0.01},
        Expected{DmcTask::kWalkerWalk, 24, 6, 0.025}}) {
    DmcEnv env(Single(e.task));
    SCOPED_TRACE(env.id());
    EXPECT_EQ(env.spec().env_obs_space.flat_size(), e.obs);
    EXPECT_EQ(env.spec().action_space.flat_size(), e.action);
    EXPECT_EQ(env.spec().task_obs_space.flat_size(), 0);
    EXPECT_EQ(env.spec().max_episode_steps, 1000);
    EXPECT_EQ(env.model()->nu, e.action);
    env.Seed(3);
    env.Reset();
    EXPECT_EQ(env.data()->time, 0.0);
    const std::vector<float> zero(e.action, 0.0f);
    for (int t = 1; t <= 1000; ++t) {
      const StepResult r = env.Step(zero);
      ASSERT_FALSE(r.terminated) << t;
      ASSERT_EQ(r.truncated, t == 1000) << t;
      ASSERT_GE(r.reward, 0.0f);
      ASSERT_LE(r.reward, 1.0f);
      ASSERT_EQ(Info(r, "sim_warnings"), 0.0f);
      if (t == 1) {
        EXPECT_NEAR(env.data()->time, e.control_dt, 1e-12);
      }
    }
    // 1000 control steps: dm_control's 20, 10 and 25 seconds
    EXPECT_NEAR(env.data()->time, 1000 * e.control_dt, 1e-9);
    EXPECT_TRUE(env.needs_reset());
  }
}

TEST(DmcEnvTest, RewardFunctionsOnHandComputedCases) {
  EXPECT_EQ(FingerSpinReward(-15.0), 1.0);
  EXPECT_EQ(FingerSpinReward(-40.0), 1.0);
  EXPECT_EQ(FingerSpinReward(-14.999), 0.0);
  EXPECT_EQ(FingerSpinReward(20.0), 0.0);
  EXPECT_EQ(CheetahRunReward(-3.0), 0.0);
  EXPECT_EQ(CheetahRunReward(0.0), 0.0);
  EXPECT_NEAR(CheetahRunReward(2.5), 0.25, 1e-15);
  EXPECT_EQ(CheetahRunReward(10.0), 1.0);
  EXPECT_EQ(CheetahRunReward(30.0), 1.0);
  // upright, standing, walking at 1 m/s: everything full
  EXPECT_EQ(WalkerWalkReward(1.3, 1.0, 1.0), 1.0);
  // one margin (0.6 m) too low: standing 0.1, so stand = (0.3 + 1) / 4
  EXPECT_NEAR(WalkerWalkReward(0.6, 1.0, 2.0), 0.325, 1e-12);
  // lying flat (upright 0 -> 1/2): stand = (3 + 0.5) / 4; at 0.5 m/s move = 0.5
  EXPECT_NEAR(WalkerWalkReward(1.2, 0.0, 0.5), 0.875 * 3.5 / 6.0, 1e-12);
  // standing still: move 0 leaves a sixth of stand
  EXPECT_NEAR(WalkerWalkReward(1.2, 0.0, 0.0), 0.875 / 6.0, 1e-12);
  // upside down on the floor, going backwards
  EXPECT_NEAR(WalkerWalkReward(0.0, -1.0, -1.0), 3.0 * std::pow(0.1, 4.0) / 4.0 / 6.0, 1e-12);
}

TEST(DmcEnvTest, RewardsAndObservationsReadTheSimulator) {
  for (const DmcTask task : {DmcTask::kFingerSpin, DmcTask::kCheetahRun, DmcTask::kWalkerWalk}) {
    DmcEnv env(Single(task));
    SCOPED_TRACE(env.id());
    env.Seed(5);
    env.Reset();
    const mjModel* m = env.model();
    const mjData* d = env.data();
    Rng rng(9);
    for (int t = 0; t < 100; ++t) {
      const StepResult r = env.Step(RandomAction(rng, m->nu));
      const std::vector<float>& obs = r.obs.env_obs;
      switch (task) {
        case DmcTask::kFingerSpin: {
          // angles, tip relative to the spinner, velocities, log(1 + touch)
          ASSERT_FLOAT_EQ(obs[0], d->qpos[0]);
          ASSERT_FLOAT_EQ(obs[1], d->qpos[1]);
          const int tip = mj_name2id(m, mjOBJ_SITE, "tip");
          const int spinner = mj_name2id(m, mjOBJ_BODY, "spinner");
          ASSERT_NEAR(obs[2], d->site_xpos[3 * tip] - d->xpos[3 * spinner], 1e-6);
          ASSERT_NEAR(obs[3], d->site_xpos[3 * tip + 2] - d->xpos[3 * spinner + 2], 1e-6);
          for (int i = 0; i < 3; ++i) ASSERT_FLOAT_EQ(obs[4 + i], d->qvel[i]);
          ASSERT_GE(obs[7], 0.0f);
          ASSERT_GE(obs[8], 0.0f);
          ASSERT_FLOAT_EQ(Info(r, "hinge_velocity"), d->qvel[2]);
          ASSERT_EQ(r.reward, static_cast<float>(FingerSpinReward(d->qvel[2])));
          break;
        }
        case DmcTask::kCheetahRun: {
          for (int i = 1; i < 9; ++i) ASSERT_FLOAT_EQ(obs[i - 1], d->qpos[i]);
          for (int i = 0; i < 9; ++i) ASSERT_FLOAT_EQ(obs[8 + i], d->qvel[i]);
          // the torso's subtree is the whole cheetah: its centre-of-mass velocity
          ASSERT_NEAR(Info(r, "com_velocity"), d->subtree_linvel[3], 1e-5);
          ASSERT_EQ(r.reward, static_cast<float>(CheetahRunReward(d->sensordata[0])));
          break;
        }
        case DmcTask::kWalkerWalk: {
          for (int b = 1; b <= 7; ++b) {
            ASSERT_FLOAT_EQ(obs[2 * (b - 1)], d->xmat[9 * b]);
            ASSERT_FLOAT_EQ(obs[2 * (b - 1) + 1], d->xmat[9 * b + 2]);
          }
          ASSERT_FLOAT_EQ(obs[14], d->xpos[5]);
          for (int i = 0; i < 9; ++i) ASSERT_FLOAT_EQ(obs[15 + i], d->qvel[i]);
          ASSERT_FLOAT_EQ(Info(r, "torso_height"), d->xpos[5]);
          ASSERT_FLOAT_EQ(Info(r, "torso_upright"), d->xmat[9 + 8]);
          ASSERT_NEAR(Info(r, "com_velocity"), d->subtree_linvel[3], 1e-5);
          ASSERT_EQ(r.reward, static_cast<float>(
                                  WalkerWalkReward(d->xpos[5], d->xmat[9 + 8], d->sensordata[0])));
          break;
        }
      }
    }
  }
}

TEST(DmcEnvTest, InitialStatesAreDrawnAsDmControlDoes) {
  DmcEnv finger(Single(DmcTask::kFingerSpin));
  DmcEnv cheetah(Single(DmcTask::kCheetahRun));
  DmcEnv walker(Single(DmcTask::kWalkerWalk));
  // the spin task's damping of the spinner hinge
  EXPECT_DOUBLE_EQ(finger.model()->dof_damping[2], 0.03);
  std::set<double> spinner_angles, pitches;
  for (uint64_t seed = 0; seed < 20; ++seed) {
    finger.Seed(seed);
    finger.Reset();
    EXPECT_EQ(finger.data()->ncon, 0);  // drawn until nothing touches
    for (int i = 0; i < 3; ++i) EXPECT_EQ(finger.data()->qvel[i], 0.0);
    const double range = 110.0 * M_PI / 180.0;
    EXPECT_LE(std::abs(finger.data()->qpos[0]), range + 1e-12);
    EXPECT_LE(std::abs(finger.data()->qpos[1]), range + 1e-12);
    EXPECT_LE(std::abs(finger.data()->qpos[2]), M_PI);
    spinner_angles.insert(finger.data()->qpos[2]);

    cheetah.Seed(seed);
    cheetah.Reset();
    EXPECT_EQ(cheetah.data()->time, 0.0);  // after the 2 s of settling
    // settled: on the ground, nearly at rest
    EXPECT_LT(std::abs(cheetah.data()->qvel[1]), 0.5);

    walker.Seed(seed);
    walker.Reset();
    EXPECT_DOUBLE_EQ(walker.data()->xpos[5], 1.3);  // torso origin, not yet fallen
    EXPECT_EQ(walker.data()->qpos[0], 0.0);         // rootz
    EXPECT_EQ(walker.data()->qpos[1], 0.0);         // rootx
    for (int i = 0; i < 9; ++i) EXPECT_EQ(walker.data()->qvel[i], 0.0);
    pitches.insert(walker.data()->qpos[2]);
  }
  EXPECT_EQ(spinner_angles.size(), 20u);
  // the torso pitch covers the full circle
  EXPECT_LT(*pitches.begin(), -M_PI / 2);
  EXPECT_GT(*pitches.rbegin(), M_PI / 2);
}

TEST(DmcEnvTest, SameSeedsGiveTheSameTrajectoryAndOtherSeedsAnother) {
  auto run = [](uint64_t seed) {
    DmcEnv env(Single(DmcTask::kWalkerWalk));
    env.Seed(seed);
    std::vector<float> trace = env.Reset().env_obs;
    Rng rng(4);
    for (int t = 0; t < 50; ++t) {
      const StepResult r = env.Step(RandomAction(rng, 6));
      trace.insert(trace.end(), r.obs.env_obs.begin(), r.obs.env_obs.end());
      trace.push_back(r.reward);
    }
    return trace;
  };
  EXPECT_EQ(run(1), run(1));
  EXPECT_NE(run(1), run(2));
}

TEST(DmcVariantTest, TaskStatesRoundTripAndTheTaskObservationIsTheIndex) {
  for (const Variation v : {Variation::kFingerSize, Variation::kCheetahTorsoLength,
                            Variation::kWalkerFriction, Variation::kWalkerFootLength}) {
    DmcEnv env(Multi(v));
    SCOPED_TRACE(env.id());
    EXPECT_EQ(env.spec().task_obs_space.flat_size(), 1);
    EXPECT_TRUE(env.spec().task_obs_space.is_discrete());
    for (int k = 0; k < kNumVariants; ++k) {
      const TaskState state{env.id(), {{"variant", k}}};
      env.SetTaskState(state);
      EXPECT_EQ(env.GetTaskState(), state);
      EXPECT_EQ(TaskState::Parse(env.GetTaskState().Dump()), state);
      EXPECT_EQ(env.variant(), k);
      EXPECT_EQ(env.task_obs()[0], static_cast<float>(k));
      EXPECT_EQ(env.Reset().task_obs, std::vector<float>{static_cast<float>(k)});
    }
    for (const nlohmann::json& bad :
         {nlohmann::json{{"variant", 10}}, nlohmann::json{{"variant", -1}},
          nlohmann::json{{"variant", 1.5}}, nlohmann::json::object(),
          nlohmann::json{{"variant", 1}, {"size", 2}}}) {
      EXPECT_THROW(env.SetTaskState(TaskState{env.id(), bad}), TaskStateError) << bad;
    }
  }
  DmcEnv single(Single(DmcTask::kCheetahRun));
  single.SetTaskState(TaskState{single.id(), nlohmann::json::object()});
  EXPECT_EQ(single.GetTaskState(), (TaskState{single.id(), nlohmann::json::object()}));
  EXPECT_THROW(single.SetTaskState(TaskState{single.id(), {{"variant", 1}}}), TaskStateError);
  EXPECT_TRUE(single.EvaluationTasks().empty());
}

TEST(DmcVariantTest, EachVariantChangesItsPhysicalParameter) {
  {
    DmcEnv env(Multi(Variation::kFingerSize));
    for (int k = 0; k < kNumVariants; ++k) {
      env.SetTaskState({env.id(), {{"variant", k}}});
      const mjModel* m = env.model();
      for (const char* site : {"touchtop", "touchbottom"}) {
        const int s = mj_name2id(m, mjOBJ_SITE, site);
        EXPECT_NEAR(m->site_size[3 * s], 0.025 * (k + 1), 1e-12) << site;
        EXPECT_EQ(m->site_size[3 * s + 1], 0.03);
      }
    }
  }
  {
    DmcEnv env(Multi(Variation::kCheetahTorsoLength));
    double previous_torso_mass = 0.0;
    for (int k = 0; k < kNumVariants; ++k) {
      env.SetTaskState({env.id(), {{"variant", k}}});
      const mjModel* m = env.model();
      const int torso = mj_name2id(m, mjOBJ_GEOM, "torso");
      EXPECT_NEAR(m->geom_size[3 * torso + 1], 0.5 + 0.1 * k, 1e-12);
      EXPECT_NEAR(mj_getTotalmass(m), 14.0, 1e-9);  // settotalmass: the legs get lighter
      const double torso_mass = m->body_mass[mj_name2id(m, mjOBJ_BODY, "torso")];
      EXPECT_GT(torso_mass, previous_torso_mass);
      previous_torso_mass = torso_mass;
    }
  }
  {
    DmcEnv env(Multi(Variation::kWalkerFriction));
    for (int k = 0; k < kNumVariants; ++k) {
      env.SetTaskState({env.id(), {{"variant", k}}});
      const mjModel* m = env.model();
      for (int g = 0; g < m->ngeom; ++g) {  // the floor and every body geom
        EXPECT_NEAR(m->geom_friction[3 * g], 0.7 + 0.1 * k, 1e-12) << g;
      }
    }
  }
  {
    DmcEnv env(Multi(Variation::kWalkerFootLength));
    for (int k = 0; k < kNumVariants; ++k) {
      env.SetTaskState({env.id(), {{"variant", k}}});
      const mjModel* m = env.model();
      EXPECT_NEAR(m->geom_size[3 * mj_name2id(m, mjOBJ_GEOM, "left_foot") + 1], 0.08 + 0.01 * k,
                  1e-12);
      EXPECT_EQ(m->geom_size[3 * mj_name2id(m, mjOBJ_GEOM, "right_foot") + 1], 0.1);
    }
  }
}

TEST(DmcVariantTest, AVariantChangesTheTrajectoryAndTheBaseVariantIsTheSingleTask) {
  auto returns = [](DmcEnv& env, int variant) {
    if (env.spec().task_obs_space.flat_size() > 0) {
      env.SetTaskState({env.id(), {{"variant", variant}}});
    }
    env.Seed(2);
    env.Reset();
    Rng rng(6);
    std::vector<float> trace;
    for (int t = 0; t < 200; ++t) {
      const StepResult r = env.Step(RandomAction(rng, 6));
      trace.push_back(r.obs.env_obs[0]);
      trace.push_back(r.reward);
    }
    return trace;
  };
  for (const Variation v :
       {Variation::kCheetahTorsoLength, Variation::kWalkerFriction, Variation::kWalkerFootLength}) {
    DmcEnv env(Multi(v));
    DmcEnv single(Single(TaskOf(v)));
    SCOPED_TRACE(env.id());
    EXPECT_NE(returns(env, 0), returns(env, 9));
    // variant 0 of torso length and friction is dm_control's model; foot length's is variant 2
    const int base = v == Variation::kWalkerFootLength ? 2 : 0;
    EXPECT_EQ(returns(env, base), returns(single, 0));
  }
}

TEST(DmcVariantTest, FingerSizesChangeOnlyTheTouchReadings) {
  // Sites have no mass and do not collide: the dynamics are the same, only the touch
  // sensors count contacts inside a larger ellipsoid.
  auto run = [](int variant) {
    DmcEnv env(Multi(Variation::kFingerSize));
    env.SetTaskState({env.id(), {{"variant", variant}}});
    env.Seed(1);
    std::vector<std::vector<float>> trace = {env.Reset().env_obs};
    Rng rng(3);
    for (int t = 0; t < 1000; ++t) trace.push_back(env.Step(RandomAction(rng, 2)).obs.env_obs);
    return trace;
  };
  const auto small = run(0), large = run(9);
  int touch_differs = 0;
  for (size_t t = 0; t < small.size(); ++t) {
    for (int i = 0; i < 7; ++i) ASSERT_EQ(small[t][i], large[t][i]) << t << " " << i;
    touch_differs += small[t][7] != large[t][7] || small[t][8] != large[t][8];
  }
  std::printf("touch readings differ at %d of %zu steps\n", touch_differs, small.size());
  EXPECT_GT(touch_differs, 0);
}

TEST(DmcVariantTest, CompiledModelsAreSharedPerVariant) {
  DmcEnv a(Multi(Variation::kCheetahTorsoLength));
  DmcEnv b(Multi(Variation::kCheetahTorsoLength));
  a.SetTaskState({a.id(), {{"variant", 4}}});
  b.SetTaskState({b.id(), {{"variant", 4}}});
  EXPECT_EQ(a.model(), b.model());
  EXPECT_NE(a.data(), b.data());
  b.SetTaskState({b.id(), {{"variant", 5}}});
  EXPECT_NE(a.model(), b.model());
}

TEST(DmcVariantTest, MtrlSplitSamplesTheTrainVariantsAndEvaluatesThreeGroups) {
  DmcEnv all(Multi(Variation::kFingerSize));
  const std::vector<TaskGroup> groups = all.EvaluationTasks();
  ASSERT_EQ(groups.size(), 10u);
  EXPECT_EQ(groups[0].name, "touch_site_x=0.025");
  EXPECT_EQ(groups[9].name, "touch_site_x=0.25");
  EXPECT_EQ(groups[3].states, (std::vector<TaskState>{{all.id(), {{"variant", 3}}}}));

  DmcEnv mtrl(
      {.task = DmcTask::kFingerSpin, .variation = Variation::kFingerSize, .split = Split::kMtrl});
  std::set<int> sampled;
  mtrl.SeedTask(1);
  for (int i = 0; i < 200; ++i) sampled.insert(mtrl.SampleTaskState().params["variant"].get<int>());
  EXPECT_EQ(sampled, (std::set<int>{3, 4, 7, 8}));
  const std::vector<TaskGroup> split = mtrl.EvaluationTasks();
  ASSERT_EQ(split.size(), 3u);
  auto variants = [](const TaskGroup& g) {
    std::vector<int> v;
    for (const TaskState& s : g.states) v.push_back(s.params["variant"].get<int>());
    return v;
  };
  EXPECT_EQ(split[0].name, "train");
  EXPECT_EQ(variants(split[0]), (std::vector<int>{3, 4, 7, 8}));
  EXPECT_EQ(split[1].name, "interpolation");
  EXPECT_EQ(variants(split[1]), (std::vector<int>{5, 6}));
  EXPECT_EQ(split[2].name, "extrapolation");
  EXPECT_EQ(variants(split[2]), (std::vector<int>{2, 9}));
  // held-out variants can still be set, for evaluation
  mtrl.SetTaskState({mtrl.id(), {{"variant", 9}}});
  EXPECT_EQ(mtrl.variant(), 9);
}

TEST(DmcEnvTest, TheFirstCameraIsTheDefaultOneAndTheSceneXmlReloads) {
  for (const DmcTask task : {DmcTask::kFingerSpin, DmcTask::kCheetahRun, DmcTask::kWalkerWalk}) {
    DmcEnv env(Single(task));
    SCOPED_TRACE(env.id());
    ASSERT_GE(env.model()->ncam, 1);
    EXPECT_EQ(std::string(mj_id2name(env.model(), mjOBJ_CAMERA, 0)), env.default_camera());
    EXPECT_EQ(env.ActiveScene().model, env.model());
  }
}

}  // namespace
}  // namespace manyworlds::dmc

#endif  // MANYWORLDS_DMC_HAS_ENVS
