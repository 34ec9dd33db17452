// Benchmarks: variation sets, splits, goal visibility, one-hot ids, task
// states, scripted policies and MJCF export through the registry.
#include "manyworlds/manipulation/benchmark.h"

#include <algorithm>
#include <cstdio>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "manyworlds/core/env_checker.h"
#include "manyworlds/core/error.h"
#include "manyworlds/core/wrappers/append_task_one_hot.h"
#include "manyworlds/manipulation/manipulation.h"
#include "manyworlds/sim/model.h"

namespace manyworlds::manipulation {
namespace {

class BenchmarkTest : public ::testing::Test {
 protected:
  void SetUp() override { RegisterManipulationSuite(registry_); }
  std::unique_ptr<Env> Make(const std::string& id, const nlohmann::json& options = {}) {
    return registry_.Make(id, options.is_null() ? nlohmann::json::object() : options);
  }
  Registry registry_;
};

const Benchmark& AsBenchmark(const Env& env) {
  if (const auto* bench = dynamic_cast<const Benchmark*>(&env)) return *bench;
  return dynamic_cast<const Benchmark&>(dynamic_cast<const Wrapper&>(env).inner());
}

std::set<std::string> Dumps(const std::vector<TaskState>& states) {
  std::set<std::string> dumps;
  for (const auto& s : states) dumps.insert(s.ToJson().dump());
  return dumps;
}

TEST_F(BenchmarkTest, SplitsFollowTheReference) {
  EXPECT_EQ(Mt10Tasks().size(), 10u);
  EXPECT_EQ(Ml10TrainTasks().size(), 10u);
  EXPECT_EQ(Ml10TestTasks().size(), 5u);
  const std::vector<std::string> train = Ml10TrainTasks();
  for (const auto& t : Ml10TestTasks()) {
    EXPECT_EQ(std::count(train.begin(), train.end(), t), 0) << t;
  }
  auto mt10 = Make("mt10");
  EXPECT_EQ(AsBenchmark(*mt10).config().tasks, Mt10Tasks());
  auto ml10_test = Make("ml10", {{"split", "test"}});
  EXPECT_EQ(AsBenchmark(*ml10_test).config().tasks, Ml10TestTasks());
  EXPECT_THROW(Make("ml10", {{"split", "validation"}}), ConfigError);
  EXPECT_THROW(Make("mt1", {{"task", "reech"}}), ConfigError);
}

TEST_F(BenchmarkTest, FiftyDistinctVariationsFromTheBenchmarkSeedOnly) {
  auto a = Make("mt1", {{"task", "push"}});
  auto b = Make("mt1", {{"task", "push"}});
  b->SeedTask(99);  // the task seed picks among variations, never changes them
  b->Seed(7);
  const auto& va = AsBenchmark(*a).variations(0);
  ASSERT_EQ(va.size(), 50u);
  EXPECT_EQ(Dumps(va).size(), 50u);
  EXPECT_EQ(Dumps(va), Dumps(AsBenchmark(*b).variations(0)));
  auto other_seed = Make("mt1", {{"task", "push"}, {"benchmark_seed", 1}});
  EXPECT_NE(Dumps(va), Dumps(AsBenchmark(*other_seed).variations(0)));
  // The same task has the same train variations in every benchmark.
  auto mt10 = Make("mt10");
  EXPECT_EQ(Dumps(va), Dumps(AsBenchmark(*mt10).variations(1)));
}

TEST_F(BenchmarkTest, Ml1TestVariationsDifferFromTrain) {
  auto train = Make("ml1", {{"task", "reach"}});
  auto test = Make("ml1", {{"task", "reach"}, {"split", "test"}});
  const auto train_set = Dumps(AsBenchmark(*train).variations(0));
  for (const auto& d : Dumps(AsBenchmark(*test).variations(0))) {
    EXPECT_EQ(train_set.count(d), 0u);
  }
}

TEST_F(BenchmarkTest, GoalVisibleInMtHiddenInMl) {
  auto mt = Make("mt1", {{"task", "reach"}});
  mt->ResetTaskState();
  Observation o = mt->Reset();
  ASSERT_EQ(o.env_obs.size(), 39u);  // no one-hot by default, as v3
  ASSERT_EQ(o.task_obs.size(), 1u);
  EXPECT_NE(o.env_obs[kObsGoal] + o.env_obs[kObsGoal + 1], 0.0f);
  auto ml = Make("ml1", {{"task", "reach"}});
  ml->ResetTaskState();
  o = ml->Reset();
  ASSERT_EQ(o.env_obs.size(), 39u);
  EXPECT_TRUE(o.task_obs.empty());
  for (int i = 0; i < 3; ++i) EXPECT_EQ(o.env_obs[kObsGoal + i], 0.0f);
}

TEST_F(BenchmarkTest, Mt10AppendsTheOneHotTaskIdWhenAsked) {
  auto env = Make("mt10", {{"task_id_in_obs", true}});
  const Benchmark& bench = AsBenchmark(*env);
  ASSERT_EQ(env->spec().env_obs_space.flat_size(), 49);
  for (int task = 0; task < bench.num_tasks(); ++task) {
    env->SetTaskState(bench.VariationState(task, task));
    const Observation o = env->Reset();
    ASSERT_EQ(o.task_obs.size(), 1u);
    EXPECT_EQ(o.task_obs[0], static_cast<float>(task));
    for (int j = 0; j < 10; ++j) EXPECT_EQ(o.env_obs[39 + j], j == task ? 1.0f : 0.0f);
    EXPECT_TRUE(env->spec().env_obs_space.Contains(o.env_obs));
  }
  auto no_one_hot = Make("mt10");
  EXPECT_EQ(no_one_hot->spec().env_obs_space.flat_size(), 39);
}

TEST_F(BenchmarkTest, PublishedSplitsAreV3sListsInV3sOrder) {
  // Sizes, disjointness and the order facts v3's env_dict.py fixes (one-hot index = position).
  const std::vector<std::string> all = Mt50Tasks();
  ASSERT_EQ(all.size(), 50u);
  EXPECT_EQ(std::set<std::string>(all.begin(), all.end()).size(), 50u);
  EXPECT_EQ(all.front(), "assembly");
  EXPECT_EQ(all[17], "hand-insert");  // v3 lists it before drawer-close
  EXPECT_EQ(all.back(), "window-close");
  const BenchmarkSplits& mt25 = PublishedBenchmark("mt25");
  ASSERT_EQ(mt25.train.size(), 25u);
  const std::vector<std::string> mt10 = Mt10Tasks();
  EXPECT_EQ(std::vector<std::string>(mt25.train.begin(), mt25.train.begin() + 10), mt10);
  EXPECT_EQ(mt25.train[10], "coffee-pull");
  EXPECT_EQ(mt25.train[24], "dial-turn");
  const BenchmarkSplits& ml45 = PublishedBenchmark("ml45");
  ASSERT_EQ(ml45.train.size(), 45u);
  ASSERT_EQ(ml45.test.size(), 5u);
  std::set<std::string> ml45_all(ml45.train.begin(), ml45.train.end());
  ml45_all.insert(ml45.test.begin(), ml45.test.end());
  EXPECT_EQ(ml45_all, std::set<std::string>(all.begin(), all.end()));
  const BenchmarkSplits& ml25 = PublishedBenchmark("ml25");
  EXPECT_EQ(ml25.train, mt25.train);
  ASSERT_EQ(ml25.test.size(), 5u);
  // v3's ML25 has basketball on both sides; every other test task is held out.
  for (const auto& t : ml25.test) {
    EXPECT_EQ(std::count(ml25.train.begin(), ml25.train.end(), t), t == "basketball" ? 1 : 0) << t;
  }
  for (const BenchmarkSplits& b : PublishedBenchmarks()) {
    for (const auto& t : b.train) EXPECT_EQ(std::count(all.begin(), all.end(), t), 1) << b.id;
    for (const auto& t : b.test) EXPECT_EQ(std::count(all.begin(), all.end(), t), 1) << b.id;
  }
  EXPECT_THROW(PublishedBenchmark("mt20"), ConfigError);
}

TEST_F(BenchmarkTest, EveryPublishedBenchmarkBuildsWithItsTasksInOrder) {
  for (const BenchmarkSplits& b : PublishedBenchmarks()) {
    for (const char* split : {"train", "test"}) {
      if (!b.meta && std::string(split) == "test") continue;
      nlohmann::json options = {{"num_variations", 2}};
      if (b.meta) options["split"] = split;
      auto env = Make(b.id, options);
      const Benchmark& bench = AsBenchmark(*env);
      EXPECT_EQ(bench.config().tasks, std::string(split) == "train" ? b.train : b.test) << b.id;
      EXPECT_EQ(bench.config().meta, b.meta) << b.id;
      EXPECT_EQ(env->spec().env_obs_space.flat_size(), 39) << b.id;
      const std::vector<TaskGroup> groups = env->EvaluationTasks();
      ASSERT_EQ(groups.size(), bench.config().tasks.size()) << b.id;
      env->SetTaskState(bench.VariationState(bench.num_tasks() - 1, 1));
      const Observation o = env->Reset();
      if (b.meta) {
        EXPECT_TRUE(o.task_obs.empty()) << b.id;
      } else {
        ASSERT_EQ(o.task_obs.size(), 1u) << b.id;
        EXPECT_EQ(o.task_obs[0], static_cast<float>(bench.num_tasks() - 1)) << b.id;
      }
    }
  }
}

TEST_F(BenchmarkTest, TaskStatesRunOnAnotherInstanceAndAreValidated) {
  auto a = Make("mt1", {{"task", "pick-place"}});
  auto b = Make("mt1", {{"task", "pick-place"}});
  a->SeedTask(5);
  const TaskState state = a->SampleTaskState();
  a->SetTaskState(state);
  b->SetTaskState(TaskState::FromJson(nlohmann::json::parse(state.ToJson().dump())));
  const Observation oa = a->Reset(), ob = b->Reset();
  EXPECT_EQ(oa.env_obs, ob.env_obs);

  TaskState bad = state;
  bad.params["variation"] = 50;
  EXPECT_THROW(a->SetTaskState(bad), TaskStateError);
  bad = state;
  bad.params["task"] = "push";
  EXPECT_THROW(a->SetTaskState(bad), TaskStateError);
  // A variation from another benchmark seed is refused, not silently run.
  auto other = Make("mt1", {{"task", "pick-place"}, {"benchmark_seed", 3}});
  EXPECT_THROW(other->SetTaskState(state), TaskStateError);
}

TEST_F(BenchmarkTest, PassesTheEnvChecker) {
  for (const std::string id : {"mt1", "ml1"}) {
    const CheckReport report = CheckEnv([&] { return Make(id, {{"task", "push"}}); });
    EXPECT_TRUE(report.ok()) << id << ":\n" << report.ToString();
  }
}

TEST_F(BenchmarkTest, ScriptedPolicySolvesHiddenGoalTasks) {
  auto env = Make("ml1", {{"task", "pick-place"}, {"split", "test"}});
  auto policy = MakeScriptedPolicyFor(*env);
  const auto groups = env->EvaluationTasks();
  ASSERT_EQ(groups.size(), 1u);
  ASSERT_EQ(groups[0].states.size(), 50u);
  const auto results = RolloutTaskGroups(*env, *policy, groups, 10);
  EXPECT_GE(results[0].summary.success_rate, 0.9);
}

TEST_F(BenchmarkTest, ExportedXmlLoadsAndPlacesTheVariation) {
  auto env = Make("mt1", {{"task", "push"}});
  env->SeedTask(11);
  env->ResetTaskState();
  const std::string path = ::testing::TempDir() + "/push_variation.xml";
  const SawyerTask* task = ActiveSawyerTask(*env);
  ASSERT_NE(task, nullptr);
  task->SaveVariationXml(path);
  sim::ModelPtr loaded = sim::LoadModelFromFile(path);
  EXPECT_EQ(loaded->nbody, task->model()->nbody);
  EXPECT_EQ(loaded->ngeom, task->model()->ngeom);
  const int obj = mj_name2id(loaded.get(), mjOBJ_BODY, "obj");
  ASSERT_GE(obj, 0);
  env->Reset();
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(loaded->body_pos[3 * obj + i], task->state().obj[i], 1e-5);
  }
  std::remove(path.c_str());
}

// The keyframe of an exported variation is the state a reset produces, for a
// free object and for fixtures whose joints start away from 0.
TEST_F(BenchmarkTest, ExportedKeyframeIsTheResetState) {
  for (const char* task_id : {"push", "door-close", "drawer-close", "window-close"}) {
    SCOPED_TRACE(task_id);
    auto env = Make("mt1", {{"task", task_id}});
    env->SeedTask(5);
    env->ResetTaskState();
    env->Reset();
    const SawyerTask* task = ActiveSawyerTask(*env);
    ASSERT_NE(task, nullptr);
    const std::string path = ::testing::TempDir() + "/keyframe_variation.xml";
    task->SaveVariationXml(path);
    sim::ModelPtr loaded = sim::LoadModelFromFile(path);
    std::remove(path.c_str());
    ASSERT_EQ(loaded->nkey, 1);
    ASSERT_EQ(loaded->nq, task->model()->nq);
    sim::DataPtr data = sim::MakeData(loaded.get());
    mj_resetDataKeyframe(loaded.get(), data.get(), 0);
    mj_forward(loaded.get(), data.get());
    for (int i = 0; i < loaded->nq; ++i) {
      EXPECT_NEAR(data->qpos[i], task->data()->qpos[i], 1e-9) << "qpos " << i;
    }
    const int hand = mj_name2id(loaded.get(), mjOBJ_SITE, "hand_site");
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(data->site_xpos[3 * hand + i], task->state().hand[i], 1e-6);
    }
  }
}

}  // namespace
}  // namespace manyworlds::manipulation
