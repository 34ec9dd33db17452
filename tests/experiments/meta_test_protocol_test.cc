// The meta-test protocols on an env whose episodes succeed at a step its
// goal names, so every number the protocol reports can be worked out by
// hand: Meta-World v3's metalearning_evaluation (which episodes count, in
// which order, ending at success, goals dealt to envs, rounds averaged) and
// its configuration errors; the support/query split (CS330's protocol) in
// the per_variation meta-test, in training rounds and in the algorithms that
// accept it.
#include <gtest/gtest.h>
#include <torch/torch.h>

#include <memory>
#include <set>
#include <string>
#include <vector>

#include "manyworlds/agents/actor.h"
#include "manyworlds/core/env.h"
#include "manyworlds/core/error.h"
#include "manyworlds/core/registry.h"
#include "manyworlds/experiments/evaluation/evaluator.h"
#include "manyworlds/experiments/algorithm.h"
#include "manyworlds/experiments/evaluation/meta_test_protocol.h"
#include "manyworlds/experiments/loops/collector.h"
#include "manyworlds/experiments/train_config.h"

namespace manyworlds::experiments {
namespace {

constexpr int64_t kHorizon = 10;

// Reward 1 per step; `success` from step succeed_at of every episode on
// (0: never); never terminates (the time limit truncates at 10 steps).
class TimerEnv : public Env {
 public:
  TimerEnv() : Env(Spec()) {}
  static EnvSpec Spec() {
    EnvSpec spec;
    spec.id = "timer";
    spec.description = "succeeds at a step its goal names (test env)";
    spec.action_space = Space::Box(-1.0f, 1.0f, {1});
    spec.env_obs_space = Space::Box(0.0f, 100.0f, {1});
    spec.task_obs_space = Space::Box(0.0f, 100.0f, {1});
    spec.info_fields = {"success"};
    spec.max_episode_steps = kHorizon;
    return spec;
  }

 protected:
  TaskState DoSampleTaskState(Rng& rng) override {
    return Goal(static_cast<double>(rng.UniformInt(kHorizon)));
  }
  TaskState DoGetTaskState() const override { return Goal(succeed_at_); }
  void DoSetTaskState(const TaskState& state) override {
    TaskStateReader reader(state, id());
    reader.ExpectKeys({"succeed_at"});
    succeed_at_ = reader.Number("succeed_at", 0.0, 100.0);
    const float obs[1] = {static_cast<float>(succeed_at_)};
    SetTaskObs(obs);
  }
  void DoReset(const ObsView& out) override {
    steps_ = 0;
    out.env_obs[0] = 0.0f;
  }
  void DoStep(std::span<const float>, const StepView& out) override {
    ++steps_;
    out.env_obs[0] = static_cast<float>(steps_);
    *out.reward = 1.0f;
    *out.terminated = false;
    out.info[0] = succeed_at_ > 0 && steps_ >= succeed_at_ ? 1.0f : 0.0f;
  }

 public:
  static TaskState Goal(double succeed_at) {
    return TaskState{"timer", {{"succeed_at", succeed_at}}};
  }

 private:
  double succeed_at_ = 0.0;
  int64_t steps_ = 0;
};

// Acts 0; counts the protocol's calls.
class CountingActor : public agents::Actor {
 public:
  agents::ActorState Initial(int64_t) override {
    ++initials;
    return {};
  }
  agents::ActOutput Act(const torch::Tensor& obs, const torch::Tensor&, agents::ActorState&,
                        agents::ActMode) override {
    agents::ActOutput out;
    out.action = torch::zeros({obs.size(0), 1});
    out.log_prob = torch::zeros({obs.size(0)});
    return out;
  }
  void Adapt(const torch::Tensor&, agents::ActorState&) override { ++adapts; }
  int initials = 0, adapts = 0;
};

Registry TimerRegistry() {
  Registry registry;
  registry.Add({"timer", "test", "succeeds at a step its goal names", {},
                [](const Options&) { return std::make_unique<TimerEnv>(); }});
  return registry;
}

// One held-out task with these goals (succeed_at per variation).
TaskSet OneTask(const std::vector<double>& goals, const std::string& name = "task") {
  TaskSpec task{name, "timer", {}};
  for (double g : goals) task.variations.push_back(TimerEnv::Goal(g));
  return TaskSet{{task}};
}

MetaTestConfig V3(int64_t meta_batch_size, int64_t evaluation_episodes) {
  MetaTestConfig c;
  c.protocol = kMetalearningEvaluation;
  c.meta_batch_size = meta_batch_size;
  c.num_evals = 1;
  c.adaptation_episodes = 1;
  c.evaluation_episodes = evaluation_episodes;
  return c;
}

TEST(MetalearningEvaluationTest, ATasksFirstEpisodesToEndCountAndEndAtSuccess) {
  const Registry registry = TimerRegistry();
  // env 0 gets goal 0 (success at step 3), env 1 goal 1 (never)
  const TaskSet tasks = OneTask({3, 0});
  CountingActor actor;
  MetaTestProtocol v3(tasks, registry, V3(2, 3), /*seed=*/7, 1);
  const MetaTestResult ended_at_success = v3.RunMetaTest(actor);
  // env 0's episodes end at steps 3, 6 and 9, each a success, before env 1's first ends
  ASSERT_TRUE(ended_at_success.success_rate.has_value());
  EXPECT_EQ(*ended_at_success.success_rate, 1.0);
  EXPECT_EQ(ended_at_success.mean_return, 3.0);
  // before adaptation: one 10-step episode per env, one of the two a success
  EXPECT_EQ(*ended_at_success.pre_adaptation_success_rate, 0.5);
  EXPECT_EQ(ended_at_success.pre_adaptation_return, 10.0);

  MetaTestConfig full_length = V3(2, 3);
  full_length.terminate_on_success = false;
  MetaTestProtocol v3_full(tasks, registry, full_length, 7, 1);
  const MetaTestResult r = v3_full.RunMetaTest(actor);
  // step 10: env 0 (success) then env 1 (failure); step 20: env 0 (success)
  EXPECT_DOUBLE_EQ(*r.success_rate, 2.0 / 3.0);
  EXPECT_EQ(r.mean_return, 10.0);
  ASSERT_EQ(r.episodes.size(), 2u + 3u);  // 2 adaptation, 3 evaluation episodes
  EXPECT_TRUE(r.episodes[2].evaluation);
  EXPECT_EQ(r.episodes[3].index, 1);
  EXPECT_FALSE(*r.episodes[3].success);
}

TEST(MetalearningEvaluationTest, GoalsAreDealtToEnvsAndRoundsAveraged) {
  const Registry registry = TimerRegistry();
  // four goals, two envs: env 0 holds goals 0 and 2, env 1 goals 1 and 3;
  // only goal 0 succeeds (at step 2)
  const TaskSet tasks = OneTask({2, 0, 0, 0});
  MetaTestConfig c = V3(2, 1);
  c.num_evals = 2;
  c.adaptation_steps = 2;
  c.task_select = "pseudorandom";  // each env visits each of its goals once in two rounds
  CountingActor actor;
  MetaTestProtocol protocol(tasks, registry, c, 3, 1);
  const MetaTestResult r = protocol.RunMetaTest(actor);
  // the round on goal 0 scores 1 (its episode ends first), the other 0
  EXPECT_EQ(*r.success_rate, 0.5);
  EXPECT_EQ(actor.initials, 2);  // a fresh actor every round (v3's agent.init())
  EXPECT_EQ(actor.adapts, 4);    // adaptation_steps per round
  const nlohmann::json json = r.ToJson();
  EXPECT_EQ(json["protocol"], kMetalearningEvaluation);
  EXPECT_EQ(json["num_evals"], 2);
  EXPECT_EQ(json["episodes_per_task"], 2);
  EXPECT_FALSE(json.contains("trials_per_task"));

  // two tasks: evaluation episodes are counted per task, goals per task's envs
  TaskSet two = OneTask({2, 2}, "fast");
  two.tasks.push_back(OneTask({0, 0}, "never").tasks[0]);
  MetaTestProtocol per_task(two, registry, V3(4, 3), 3, 1);
  const MetaTestResult t = per_task.RunMetaTest(actor);
  ASSERT_EQ(t.per_task.size(), 2u);
  EXPECT_EQ(*t.per_task[0].success, 1.0);
  EXPECT_EQ(t.per_task[0].mean_return, 2.0);
  EXPECT_EQ(*t.per_task[1].success, 0.0);
  EXPECT_EQ(t.per_task[1].mean_return, 10.0);
}

TEST(MetalearningEvaluationTest, BadSetupsAreConfigErrorsThatSayWhatIsAllowed) {
  const Registry registry = TimerRegistry();
  TaskSet two = OneTask({2, 2}, "a");
  two.tasks.push_back(OneTask({2, 2}, "b").tasks[0]);
  auto error_of = [&](const TaskSet& tasks, const MetaTestConfig& c) {
    try {
      MetaTestProtocol protocol(tasks, registry, c, 0, 1);
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("<no error>");
  };
  EXPECT_NE(error_of(two, V3(3, 1)).find("multiple of the number of held-out tasks (2)"),
            std::string::npos);
  EXPECT_NE(error_of(OneTask({1, 2}), V3(4, 1)).find("fewer than its 4 envs"), std::string::npos);
  MetaTestConfig bad = V3(2, 1);
  bad.protocol = "v3";
  EXPECT_NE(error_of(two, bad).find("metalearning_evaluation"), std::string::npos);
  bad = V3(2, 1);
  bad.task_select = "roundrobin";
  EXPECT_NE(error_of(two, bad).find("random, pseudorandom"), std::string::npos);
  // a config that sets a key of the other protocol says which protocol it needs
  try {
    TrainConfig::Load(std::nullopt, {"meta_test.trials_per_task=5"});
    FAIL() << "expected a ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("meta_test.protocol to per_variation"), std::string::npos)
        << e.what();
  }
  EXPECT_NO_THROW(TrainConfig::Load(
      std::nullopt, {"meta_test.protocol=per_variation", "meta_test.trials_per_task=5"}));
  // run directories from before the protocol was named keep theirs
  nlohmann::json old = TrainConfig().ToJson();
  old["meta_test"].erase("protocol");
  EXPECT_TRUE(TrainConfig::FromJson(old).meta_test.per_variation());
  EXPECT_FALSE(TrainConfig().meta_test.per_variation());
}

// Groups of 2 support + 2 query goals. Group 0: support never, query
// succeeds at step 3 then never; group 1: support never, query succeeds at
// steps 3 and 4.
TaskSet SplitTask() {
  TaskSet tasks = OneTask({0, 0, 3, 0, 0, 0, 3, 4});
  tasks.support_variations = 2;
  tasks.query_variations = 2;
  return tasks;
}

MetaTestConfig PerVariation(int64_t trials, int64_t exploration, int64_t evaluation) {
  MetaTestConfig c;
  c.protocol = kPerVariation;
  c.trials_per_task = trials;
  c.exploration_episodes = exploration;
  c.evaluation_episodes = evaluation;
  return c;
}

TEST(SupportQuerySplitTest, PerVariationAdaptsOnSupportAndScoresQueryVariations) {
  const Registry registry = TimerRegistry();
  CountingActor actor;
  const TaskSet tasks = SplitTask();  // the protocol keeps a reference
  MetaTestProtocol split(tasks, registry, PerVariation(2, 2, 2), 5, 1);
  const MetaTestResult r = split.RunMetaTest(actor);
  // trial 0 runs group 0, trial 1 group 1: three of the four query episodes succeed
  EXPECT_EQ(*r.success_rate, 0.75);
  EXPECT_EQ(*r.pre_adaptation_success_rate, 0.0);  // support goals never succeed
  EXPECT_EQ(actor.adapts, 1);
  std::vector<int> evaluation_successes;
  for (const MetaTestEpisode& e : r.episodes) {
    if (e.evaluation) evaluation_successes.push_back(*e.success ? 1 : 0);
  }
  // group 0's query episodes in order (goal 3, then never), then group 1's
  std::vector<int> order;
  for (const MetaTestEpisode& e : r.episodes) {
    if (e.evaluation && e.trial == 0) order.push_back(*e.success ? 1 : 0);
  }
  EXPECT_EQ(order, (std::vector<int>{1, 0}));
  EXPECT_EQ(evaluation_successes.size(), 4u);

  // without the split the same trials run variations 0 and 1, which never succeed
  TaskSet no_split = SplitTask();
  no_split.support_variations = no_split.query_variations = 0;
  MetaTestProtocol plain(no_split, registry, PerVariation(2, 2, 2), 5, 1);
  EXPECT_EQ(*plain.RunMetaTest(actor).success_rate, 0.0);

  // v3's protocol has no split: refused with the way out
  try {
    MetaTestProtocol v3(tasks, registry, V3(1, 1), 5, 1);
    FAIL() << "metalearning_evaluation accepted a support/query split";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("meta_test.protocol: per_variation"), std::string::npos)
        << e.what();
  }
}

TEST(SupportQuerySplitTest, TrialRoundsRunSupportThenQueryVariationsOfOneGroup) {
  const Registry registry = TimerRegistry();
  TaskSet tasks = OneTask({0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11});  // 3 groups of 2 + 2
  tasks.support_variations = 2;
  tasks.query_variations = 2;
  Collector collector(tasks, registry, /*envs_per_task=*/4, 1);
  std::set<int64_t> groups_seen, support_seen, query_seen;
  for (int64_t trial = 0; trial < 8; ++trial) {
    std::vector<int64_t> group(4, -1);
    for (int64_t k = 0; k < 3; ++k) {  // 2 support rounds, then a query round
      collector.BeginRound(/*seed=*/11, trial * 3 + k, /*rounds_per_trial=*/3,
                           /*support_rounds=*/2);
      for (int64_t i = 0; i < 4; ++i) {
        const int64_t v = collector.env_variations()[i];
        if (k == 0) group[i] = v / 4;
        EXPECT_EQ(v / 4, group[i]) << "trial " << trial << " round " << k << " env " << i;
        if (k < 2) {
          EXPECT_LT(v % 4, 2) << "support round on a query variation";
          support_seen.insert(v % 4);
        } else {
          EXPECT_GE(v % 4, 2) << "query round on a support variation";
          query_seen.insert(v % 4);
        }
      }
      groups_seen.insert(group.begin(), group.end());
    }
  }
  EXPECT_EQ(groups_seen.size(), 3u);
  EXPECT_EQ(support_seen.size(), 2u);
  EXPECT_EQ(query_seen.size(), 2u);
  // the query variations alone, for methods that do not adapt
  const TaskSet queries = tasks.QueryVariations();
  ASSERT_EQ(queries.tasks[0].variations.size(), 6u);
  EXPECT_EQ(queries.tasks[0].variations[1].params["succeed_at"], 3.0);
  EXPECT_EQ(queries.tasks[0].variations[2].params["succeed_at"], 6.0);
  EXPECT_FALSE(queries.has_split());
  // tasks.json keeps the split
  EXPECT_EQ(TaskSet::FromJson(tasks.ToJson()).query_variations, 2);
  TaskSet ragged = tasks;
  ragged.tasks[0].variations.pop_back();
  EXPECT_THROW(TaskSet::FromJson(ragged.ToJson()), ConfigError);
}

TEST(SupportQuerySplitTest, OnlyMetaLearnersWithSupportAndQueryRoundsTrainOnASplit) {
  const Registry registry = TimerRegistry();
  TaskSet tasks = OneTask({0, 1, 2, 3});
  tasks.support_variations = 2;
  tasks.query_variations = 2;
  const EnvFacts facts = InspectEnvs(tasks, registry);
  auto error_of = [&](const std::vector<std::string>& overrides) {
    try {
      BuildAlgorithm(TrainConfig::Load(std::nullopt, overrides), tasks, facts);
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("<no error>");
  };
  EXPECT_NE(error_of({"agent.algo=ppo"}).find("agent.algo 'ppo' cannot train on a support/query"),
            std::string::npos);
  EXPECT_NE(error_of({"agent.algo=sac"}).find("cannot train on a support/query"),
            std::string::npos);
  EXPECT_NE(error_of({"agent.algo=rl2", "agent.episodes_per_trial=1"}).find("rl2 with"),
            std::string::npos);
  EXPECT_EQ(error_of({"agent.algo=maml"}), "<no error>");
  EXPECT_EQ(error_of({"agent.algo=rl2", "agent.episodes_per_trial=2"}), "<no error>");
  EXPECT_EQ(error_of({"agent.algo=pearl", "replay.capacity=1000"}), "<no error>");
  // the config keys: both or neither, each >= 0
  try {
    TrainConfig::Load(std::nullopt, {"env.id=point-nav", "env.support_variations=5"}).Validate();
    FAIL() << "a support split without a query split accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("must both be 0 (no split) or both >= 1, got 5 and 0"),
              std::string::npos)
        << e.what();
  }
}

// v3's multi-task evaluation: episodes end at the first success when asked.
TEST(EvaluationTest, EpisodesEndAtSuccessWhenAsked) {
  const Registry registry = TimerRegistry();
  const TaskSet tasks = OneTask({3, 0});  // episode e runs on goal e mod 2
  const auto zeros = [](const torch::Tensor& obs, const torch::Tensor&) {
    return torch::zeros({obs.size(0), 1});
  };
  Evaluator full(tasks, registry, /*episodes_per_task=*/4, /*seed=*/1, 1);
  const EvalResult r = full.Run(zeros);
  EXPECT_EQ(*r.mean_success, 0.5);
  EXPECT_EQ(r.mean_return, 10.0);
  Evaluator v3(tasks, registry, 4, 1, 1);
  v3.TerminateOnSuccess(true);
  const EvalResult e = v3.Run(zeros);
  EXPECT_EQ(*e.mean_success, 0.5);  // the same successes
  EXPECT_EQ(e.mean_return, (3.0 + 10.0) / 2);  // the successful episodes end at step 3
  EXPECT_EQ(e.per_task[0].episodes[0].length, 3);
  EXPECT_EQ(e.per_task[0].episodes[1].length, 10);
}

}  // namespace
}  // namespace manyworlds::experiments
