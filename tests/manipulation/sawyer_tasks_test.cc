// Behaviour tests run on every registered manipulation task.
#include <cmath>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "manyworlds/core/error.h"
#include "manyworlds/manipulation/assets.h"
#include "manyworlds/manipulation/manipulation.h"
#include "manyworlds/manipulation/sawyer_task.h"
#include "manyworlds/sim/mujoco_error.h"

namespace manyworlds::manipulation {
namespace {

class SawyerTaskTest : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    RegisterManipulationSuite(registry_);
    env_ = Make();
  }
  void TearDown() override {
    // MuJoCo warnings fail every test.
    for (const auto& env : made_) {
      const auto* task = dynamic_cast<const SawyerTask*>(env.get());
      ASSERT_NE(task, nullptr);
      EXPECT_EQ(task->sim_warning_count(), 0) << task->last_sim_warning();
    }
  }
  // The fixture owns every env so TearDown can check them all.
  Env* Make(const nlohmann::json& options = nlohmann::json::object()) {
    made_.push_back(registry_.Make(GetParam(), options));
    return made_.back().get();
  }
  SawyerTask& task() { return dynamic_cast<SawyerTask&>(*env_); }

  Registry registry_;
  std::vector<std::unique_ptr<Env>> made_;
  Env* env_ = nullptr;
};

TEST_P(SawyerTaskTest, SpecFollowsTheSharedContract) {
  const EnvSpec& spec = env_->spec();
  EXPECT_EQ(spec.action_space, Space::Box(-1.0f, 1.0f, {4}));
  EXPECT_EQ(spec.env_obs_space.flat_size(), kObsSize);
  EXPECT_EQ(spec.task_obs_space.flat_size(), 3);
  EXPECT_EQ(spec.max_episode_steps, 500);
  for (const char* field : {"success", "near_object", "grasp_success", "grasp_reward",
                            "in_place_reward", "obj_to_target", "unscaled_reward"}) {
    EXPECT_GE(spec.InfoIndex(field), 0) << field;
  }
  EXPECT_EQ(task().model()->opt.timestep, 0.0025);
}

TEST_P(SawyerTaskTest, GoalsLieInsideTheirObservationBounds) {
  // The goal's bounds are v3's goal_space where it is not the goal range
  // (SawyerTaskConfig::goal_space); every goal a task draws lies inside
  // them, in the task observation and in obs[36:39].
  const EnvSpec& spec = env_->spec();
  env_->SeedTask(17);
  for (int i = 0; i < 30; ++i) {
    env_->ResetTaskState();
    ASSERT_TRUE(spec.task_obs_space.Contains(env_->task_obs())) << "variation " << i;
    const Observation obs = env_->Reset();
    for (int k = 0; k < 3; ++k) {
      EXPECT_GE(obs.env_obs[kObsGoal + k], spec.env_obs_space.low()[kObsGoal + k]) << i;
      EXPECT_LE(obs.env_obs[kObsGoal + k], spec.env_obs_space.high()[kObsGoal + k]) << i;
      EXPECT_EQ(spec.env_obs_space.low()[kObsGoal + k], spec.task_obs_space.low()[k]);
      EXPECT_EQ(spec.env_obs_space.high()[kObsGoal + k], spec.task_obs_space.high()[k]);
    }
  }
}

TEST_P(SawyerTaskTest, ResetsAreDeterministicBySeed) {
  auto other = Make();
  for (Env* env : {env_, other}) {
    env->Seed(5);
    env->SeedTask(11);
  }
  RandomPolicy policy_a(env_->spec().action_space, 3), policy_b(env_->spec().action_space, 3);
  for (int episode = 0; episode < 2; ++episode) {
    env_->ResetTaskState();
    other->ResetTaskState();
    ASSERT_EQ(env_->GetTaskState(), other->GetTaskState());
    Observation a = env_->Reset(), b = other->Reset();
    ASSERT_EQ(a.env_obs, b.env_obs);
    std::vector<float> action_a(4), action_b(4);
    for (int t = 0; t < 60; ++t) {
      policy_a.Act(a.env_obs, a.task_obs, action_a);
      policy_b.Act(b.env_obs, b.task_obs, action_b);
      StepResult ra = env_->Step(action_a), rb = other->Step(action_b);
      ASSERT_EQ(ra.obs.env_obs, rb.obs.env_obs) << "step " << t;
      ASSERT_EQ(ra.reward, rb.reward);
      ASSERT_EQ(ra.info.values, rb.info.values);
      a = ra.obs;
      b = rb.obs;
    }
  }
  // A reset does not depend on the previous episode.
  const TaskState state = env_->GetTaskState();
  other->SetTaskState(state);
  EXPECT_EQ(env_->Reset().env_obs, other->Reset().env_obs);
}

TEST_P(SawyerTaskTest, ObjectsAndHandAtRestAfterReset) {
  const std::vector<float> zero(4, 0.0f);
  env_->SeedTask(3);
  for (int variation = 0; variation < 3; ++variation) {
    env_->ResetTaskState();
    const Observation start = env_->Reset();
    Observation obs = start;
    for (int t = 0; t < 50; ++t) obs = env_->Step(zero).obs;
    for (int i = 0; i < 7; ++i) {
      EXPECT_NEAR(obs.env_obs[kObsObj1Pos + i], start.env_obs[kObsObj1Pos + i], 1e-4)
          << "object value " << i;
    }
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(obs.env_obs[kObsHand + i], start.env_obs[kObsHand + i], 1e-3) << "hand " << i;
      EXPECT_NEAR(start.env_obs[kObsHand + i], task().config().hand_init[i], 2e-3);
    }
  }
}

TEST_P(SawyerTaskTest, RewardsBoundedAndFiniteUnderRandomActions) {
  env_->SeedTask(21);
  RandomPolicy policy(env_->spec().action_space, 9);
  const int success = env_->spec().InfoIndex("success");
  const int unscaled = env_->spec().InfoIndex("unscaled_reward");
  for (int episode = 0; episode < 2; ++episode) {
    env_->ResetTaskState();
    Observation obs = env_->Reset();
    std::vector<float> action(4);
    for (int t = 0; t < 250; ++t) {
      policy.Act(obs.env_obs, obs.task_obs, action);
      StepResult r = env_->Step(action);
      ASSERT_TRUE(std::isfinite(r.reward));
      ASSERT_GE(r.reward, 0.0f);
      ASSERT_LE(r.reward, 10.0f);
      ASSERT_EQ(r.info.values[unscaled], r.reward);
      ASSERT_TRUE(r.info.values[success] == 0.0f || r.info.values[success] == 1.0f);
      for (float v : r.info.values) ASSERT_TRUE(std::isfinite(v));
      ASSERT_TRUE(env_->spec().env_obs_space.Contains(r.obs.env_obs)) << "step " << t;
      ASSERT_FALSE(r.terminated);
      obs = r.obs;
    }
  }
}

TEST_P(SawyerTaskTest, RewardIsAPureFunctionOfTheStateRecord) {
  // EvaluateReward on the record a step left gives that step's reward and
  // info (what the Meta-World fidelity test relies on); bad input throws.
  env_->SeedTask(4);
  env_->ResetTaskState();
  Observation obs = env_->Reset();
  RandomPolicy policy(env_->spec().action_space, 5);
  std::vector<float> action(4);
  for (int t = 0; t < 30; ++t) {
    policy.Act(obs.env_obs, obs.task_obs, action);
    const StepResult r = env_->Step(action);
    const RewardTerms again = task().EvaluateReward(task().state(), action);
    ASSERT_EQ(static_cast<float>(again.reward), r.reward) << "step " << t;
    ASSERT_EQ(again.success ? 1.0f : 0.0f, r.info.values[env_->spec().InfoIndex("success")]);
    ASSERT_EQ(static_cast<float>(again.obj_to_target),
              r.info.values[env_->spec().InfoIndex("obj_to_target")]);
    obs = r.obs;
  }
  EXPECT_THROW(task().EvaluateReward(task().state(), std::vector<float>(3)), Error);
  EXPECT_THROW(task().EvaluateReward(task().state(), std::vector<float>{0, 0, 0, NAN}), Error);
  SawyerState bad = task().state();
  bad.obj[1] = INFINITY;
  EXPECT_THROW(task().EvaluateReward(bad, action), Error);
}

TEST_P(SawyerTaskTest, NoSuccessAtTheFirstStep) {
  env_->SeedTask(8);
  const std::vector<float> zero(4, 0.0f);
  for (int variation = 0; variation < 10; ++variation) {
    env_->ResetTaskState();
    env_->Reset();
    StepResult r = env_->Step(zero);
    EXPECT_EQ(r.info.Get("success"), 0.0f) << env_->GetTaskState().Dump();
    EXPECT_LT(r.reward, 10.0f);
  }
}

TEST_P(SawyerTaskTest, ObservationMatchesSimulator) {
  env_->SeedTask(4);
  env_->ResetTaskState();
  Observation obs = env_->Reset();
  EXPECT_EQ(std::vector<float>(obs.env_obs.begin() + kObsPrev, obs.env_obs.begin() + kObsGoal),
            std::vector<float>(obs.env_obs.begin(), obs.env_obs.begin() + kObsFrame));
  RandomPolicy policy(env_->spec().action_space, 1);
  std::vector<float> action(4);
  const mjModel* m = task().model();
  const mjData* d = task().data();
  const int hand = mj_name2id(m, mjOBJ_SITE, "hand_site");
  const int left = mj_name2id(m, mjOBJ_SITE, "left_pad_site");
  const int right = mj_name2id(m, mjOBJ_SITE, "right_pad_site");
  const int obj = mj_name2id(m, mjOBJ_BODY, "obj");
  // obs[7:11]: body "obj"'s orientation, or the fixture body the task names.
  const std::string& quat_name = task().config().obj_quat_body;
  const int quat = quat_name.empty() ? obj : mj_name2id(m, mjOBJ_BODY, quat_name.c_str());
  // A task whose observed object point is not the body's origin marks it
  // with the site "obj_point" (e.g. peg-insert-side's grasp point).
  const int obj_point = mj_name2id(m, mjOBJ_SITE, "obj_point");
  const mjtNum* obj_pos = obj_point >= 0 ? d->site_xpos + 3 * obj_point : d->xpos + 3 * obj;
  const int goal = mj_name2id(m, mjOBJ_BODY, "goal");
  for (int t = 0; t < 20; ++t) {
    policy.Act(obs.env_obs, obs.task_obs, action);
    const std::vector<float> previous = obs.env_obs;
    obs = env_->Step(action).obs;
    const auto& o = obs.env_obs;
    for (int i = 0; i < 3; ++i) {
      EXPECT_FLOAT_EQ(o[kObsHand + i], static_cast<float>(d->site_xpos[3 * hand + i]));
      EXPECT_FLOAT_EQ(o[kObsObj1Pos + i], static_cast<float>(obj_pos[i]));
      EXPECT_FLOAT_EQ(o[kObsGoal + i], static_cast<float>(d->xpos[3 * goal + i]));
      EXPECT_FLOAT_EQ(obs.task_obs[i], o[kObsGoal + i]);
    }
    const double pads = mju_dist3(d->site_xpos + 3 * left, d->site_xpos + 3 * right);
    EXPECT_FLOAT_EQ(o[kObsGripper], static_cast<float>(std::min(1.0, pads / 0.1)));
    // From MuJoCo's (w, x, y, z), in the task's layout.
    switch (task().config().obj_quat) {
      case QuatLayout::kXyzw:
        EXPECT_FLOAT_EQ(o[kObsObj1Quat + 3], static_cast<float>(d->xquat[4 * quat]));
        EXPECT_FLOAT_EQ(o[kObsObj1Quat + 0], static_cast<float>(d->xquat[4 * quat + 1]));
        break;
      case QuatLayout::kWxyz:
        EXPECT_FLOAT_EQ(o[kObsObj1Quat + 0], static_cast<float>(d->xquat[4 * quat]));
        EXPECT_FLOAT_EQ(o[kObsObj1Quat + 1], static_cast<float>(d->xquat[4 * quat + 1]));
        break;
      case QuatLayout::kZeros:
        for (int i = 0; i < 4; ++i) EXPECT_EQ(o[kObsObj1Quat + i], 0.0f);
        break;
    }
    // obs[11:18]: the second object (the tool-use tasks; its place is
    // checked in tool_test.cc) as the record holds it, else zeros.
    const Vec3& obj2 = task().state().obj2;
    for (int i = 0; i < 3; ++i) EXPECT_EQ(o[kObsObj2Pos + i], static_cast<float>(obj2[i]));
    if (obj2 == Vec3{}) {
      for (int i = kObsObj2Quat; i < kObsFrame; ++i) EXPECT_EQ(o[i], 0.0f);
    }
    for (int i = 0; i < kObsFrame; ++i) EXPECT_EQ(o[kObsPrev + i], previous[i]);
  }
}

TEST_P(SawyerTaskTest, HiddenGoalIsZeroed) {
  auto hidden = Make({{"goal_observable", false}});
  EXPECT_EQ(hidden->spec().task_obs_space.flat_size(), 0);
  hidden->ResetTaskState();
  const Observation obs = hidden->Reset();
  for (int i = 0; i < 3; ++i) EXPECT_EQ(obs.env_obs[kObsGoal + i], 0.0f);
  EXPECT_TRUE(obs.task_obs.empty());
}

TEST_P(SawyerTaskTest, TaskStatesRoundTripAndAreValidated) {
  env_->SeedTask(17);
  for (int i = 0; i < 20; ++i) {
    const TaskState state = env_->SampleTaskState();
    const TaskState parsed = TaskState::Parse(state.Dump());
    EXPECT_EQ(parsed, state);
    env_->SetTaskState(parsed);
    EXPECT_EQ(env_->GetTaskState(), state);
  }
  TaskState state = env_->SampleTaskState();
  TaskState bad = state;
  bad.params["obj_pos"][1] = 0.95;  // outside the object range
  EXPECT_THROW(env_->SetTaskState(bad), TaskStateError);
  bad = state;
  bad.params["goal_pos"] = {0.0, 0.85};
  EXPECT_THROW(env_->SetTaskState(bad), TaskStateError);
  bad = state;
  bad.params["extra"] = 1;
  EXPECT_THROW(env_->SetTaskState(bad), TaskStateError);
  bad = state;
  bad.env = "other-task";
  EXPECT_THROW(env_->SetTaskState(bad), TaskStateError);
}

TEST_P(SawyerTaskTest, ScriptedPolicySucceeds) {
  auto policy = MakeScriptedPolicy(GetParam());
  env_->SeedTask(2024);
  int successes = 0;
  const int variations = 10;
  for (int variation = 0; variation < variations; ++variation) {
    env_->ResetTaskState();
    Observation obs = env_->Reset();
    policy->BeginEpisode();
    std::vector<float> action(4);
    for (int t = 0; t < 500; ++t) {
      policy->Act(obs.env_obs, obs.task_obs, action);
      StepResult r = env_->Step(action);
      if (r.info.Get("success") > 0) {
        ++successes;
        break;
      }
      obs = r.obs;
    }
  }
  EXPECT_GE(successes, 9) << GetParam();
}

INSTANTIATE_TEST_SUITE_P(AllTasks, SawyerTaskTest,
                         ::testing::ValuesIn(ManipulationTaskIds()),
                         [](const auto& info) {
                           std::string name = info.param;
                           for (char& c : name) c = c == '-' ? '_' : c;
                           return name;
                         });

TEST(ManipulationSuiteTest, RegistersTasksInOrder) {
  Registry registry;
  RegisterManipulationSuite(registry);
  std::vector<std::string> tasks;
  for (const auto& entry : registry.entries()) {
    if (entry.family == "manipulation") tasks.push_back(entry.id);
  }
  EXPECT_EQ(tasks, ManipulationTaskIds());
  EXPECT_EQ(registry.Find("push").family, "manipulation");
  EXPECT_THROW(registry.Make("reach", {{"goal_visible", true}}), ConfigError);
  EXPECT_THROW(MakeScriptedPolicy("pick-plase"), ConfigError);
}

TEST(ManipulationSuiteTest, AssetsAreEmbedded) {
  EXPECT_NE(FindAsset("sawyer_arena.xml").find("hand_weld"), std::string_view::npos);
  EXPECT_THROW(FindAsset("missing.xml"), Error);
  EXPECT_THROW(LoadTaskModel("missing.xml"), Error);
}

}  // namespace
}  // namespace manyworlds::manipulation
