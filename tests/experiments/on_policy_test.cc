// The on-policy family end to end through the Trainer: seeded learning runs
// with real thresholds (small problems, seconds each), exact resume for PPO
// and TRPO, and the errors a config gets when the algorithm cannot run it.
#include <gtest/gtest.h>
#include <torch/torch.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

#include "manyworlds/core/error.h"
#include "manyworlds/envs/all.h"
#include "manyworlds/experiments/algorithms.h"
#include "manyworlds/experiments/evaluation/evaluator.h"
#include "manyworlds/experiments/run/run_log.h"
#include "manyworlds/experiments/trainer.h"
#include "manyworlds/rl/generator.h"
#include "tests/experiments/scratch_dirs.h"

namespace manyworlds::experiments {
namespace {

namespace fs = std::filesystem;

fs::path Scratch(const std::string& name) { return test_dirs::Scratch("on_policy", name); }

TrainConfig FromFile(const std::string& name, const fs::path& run_dir,
                     std::vector<std::string> overrides = {}) {
  overrides.push_back("experiment.run_dir=" + run_dir.string());
  TrainConfig c = TrainConfig::Load(test_dirs::SourceDir() / "configs" / name, overrides);
  c.Validate();
  return c;
}

EvalResult Train(const TrainConfig& c) {
  Trainer trainer = Trainer::Create(c);
  const TrainSummary s = trainer.Run();
  EXPECT_TRUE(s.finished);
  return *s.final_eval;
}

TEST(OnPolicyLearningTest, PpoSolvesMultiTaskCartPole) {
  // four cart-poles with different physics, one-hot task id, categorical policy
  const EvalResult r = Train(FromFile("cartpole_ppo.yaml", Scratch("cartpole")));
  ASSERT_EQ(r.per_task.size(), 4u);
  for (const auto& t : r.per_task) EXPECT_GE(t.mean_return, 475.0) << t.task;  // limit 500
}

TEST(OnPolicyLearningTest, PpoSolvesPointNavigation) {
  const EvalResult r = Train(FromFile("point_nav_ppo.yaml", Scratch("ppo_nav")));
  ASSERT_TRUE(r.mean_success.has_value());
  EXPECT_GE(*r.mean_success, 0.95);
  // a mean distance to the goal under 0.03 over the episode; random: about -50
  EXPECT_GT(r.mean_return, -3.0);
}

TEST(OnPolicyLearningTest, TePpoSolvesPointNavigationWithSeparableTaskLatents) {
  const fs::path dir = Scratch("teppo");
  const EvalResult r = Train(FromFile("point_nav_teppo.yaml", dir));
  ASSERT_TRUE(r.mean_success.has_value());
  EXPECT_GE(*r.mean_success, 0.95);  // the task reaches the policy only through the latent
  EXPECT_GT(r.mean_return, -3.0);
  // the encoder keeps the tasks apart and the inference network recognises
  // the episode's latent from six observations
  const nlohmann::json last = ReadJsonLines(dir / "metrics.jsonl").back();
  EXPECT_GT(last["latent_min_distance"].get<double>(),
            3.0 * last["inference_rmse"].get<double>())
      << last.dump();
}

TEST(OnPolicyLearningTest, TrpoSolvesPointNavigation) {
  const EvalResult r = Train(FromFile("point_nav_trpo.yaml", Scratch("trpo"),
                                      {"experiment.steps_per_task=20000"}));
  ASSERT_TRUE(r.mean_success.has_value());
  EXPECT_GE(*r.mean_success, 0.95);
  EXPECT_GT(r.mean_return, -2.0);  // a random policy: about -50
}

TEST(OnPolicyLearningTest, TrpoWithALearnedTaskEncoderSolvesPointNavigation) {
  // the task reaches the policy only through the learned encoding
  const EvalResult r = Train(FromFile(
      "point_nav_trpo.yaml", Scratch("trpo_te"),
      {"experiment.steps_per_task=20000", "agent.architecture=task_encoder"}));
  ASSERT_TRUE(r.mean_success.has_value());
  EXPECT_GE(*r.mean_success, 0.95);
  EXPECT_GT(r.mean_return, -2.0);
}

TEST(OnPolicyLearningTest, TrpoWithAMixtureOfEncodersAndPcGradSolvesPointNavigation) {
  const fs::path dir = Scratch("trpo_moe");
  const EvalResult r = Train(FromFile(
      "point_nav_trpo.yaml", dir,
      {"experiment.steps_per_task=6000", "agent.architecture=moe", "agent.pcgrad=true"}));
  ASSERT_TRUE(r.mean_success.has_value());
  EXPECT_GE(*r.mean_success, 0.95);
  EXPECT_GT(r.mean_return, -2.0);
  EXPECT_TRUE(ReadJsonLines(dir / "metrics.jsonl").back().contains("pcgrad_conflicts"));
}

TEST(OnPolicyLearningTest, CategoricalPpoBeatsTheUniformPolicyOnABandit) {
  TrainConfig c = FromFile("cartpole_ppo.yaml", Scratch("bandit"),
                           {"env.id=bandit", "env.num_tasks=1", "env.envs_per_task=4",
                            "experiment.steps_per_task=3000", "experiment.eval_every=0"});
  const EvalResult trained = Train(c);
  // the uniform policy on the same task and episodes
  const RunInfo run = RunInfo::Read(c.experiment.run_dir);
  Evaluator evaluator(run.tasks, DefaultRegistry(), c.experiment.eval_episodes, 7, 1);
  at::Generator gen = rl::MakeGenerator(3);
  const EvalResult uniform = evaluator.Run([&](const torch::Tensor& obs, const torch::Tensor&) {
    return torch::randint(0, 5, {obs.size(0), 1}, gen, torch::kInt64).to(torch::kFloat32);
  });
  const auto& arms = run.tasks.tasks[0].variations[0].params["probs"];
  double best = 0;
  for (const auto& p : arms) best = std::max(best, p.get<double>());
  // 100 pulls per episode: the greedy-best arm earns 100 * best
  EXPECT_GT(trained.mean_return, uniform.mean_return + 0.5 * (100 * best - uniform.mean_return))
      << "uniform " << uniform.mean_return << ", best arm " << 100 * best;
}

std::vector<nlohmann::json> Rows(const fs::path& file) {
  std::vector<nlohmann::json> rows = ReadJsonLines(file);
  for (auto& row : rows) {
    for (const char* key : {"wall_s", "env_steps_per_s", "updates_per_s", "time_act_s",
                            "time_env_s", "time_update_s"}) {
      row.erase(key);
    }
  }
  return rows;
}

void ExpectExactResume(const std::string& config_file, std::vector<std::string> overrides,
                       const std::string& name) {
  const fs::path a = Scratch(name + "_a"), b = Scratch(name + "_b");
  overrides.push_back("experiment.checkpoint_every=1000");
  overrides.push_back("experiment.keep_checkpoints=0");
  {
    Trainer full = Trainer::Create(FromFile(config_file, a, overrides));
    ASSERT_TRUE(full.Run().finished);
  }
  {
    Trainer first = Trainer::Create(FromFile(config_file, b, overrides));
    TrainCallbacks stop;
    stop.stop_after_step = 1000;
    ASSERT_FALSE(first.Run(stop).finished);
  }
  {
    Trainer resumed = Trainer::Resume(b);
    EXPECT_GT(resumed.step(), 0);
    ASSERT_TRUE(resumed.Run().finished);
  }
  EXPECT_EQ(Rows(a / "metrics.jsonl"), Rows(b / "metrics.jsonl"));
  std::vector<nlohmann::json> ea = ReadJsonLines(a / "eval.jsonl");
  std::vector<nlohmann::json> eb = ReadJsonLines(b / "eval.jsonl");
  for (auto* rows : {&ea, &eb}) {
    for (auto& row : *rows) row.erase("wall_s");
  }
  EXPECT_EQ(ea, eb);
  ASSERT_GE(ea.size(), 2u);
  // meta-RL runs: the meta-test and meta-train logs resume exactly too
  for (const char* log : {"meta_test.jsonl", "meta_train.jsonl"}) {
    if (!fs::exists(a / log)) continue;
    std::vector<nlohmann::json> ma = ReadJsonLines(a / log), mb = ReadJsonLines(b / log);
    for (auto* rows : {&ma, &mb}) {
      for (auto& row : *rows) row.erase("wall_s");
    }
    EXPECT_EQ(ma, mb) << log;
    EXPECT_EQ(ma.size(), ea.size()) << log;
  }
}

TEST(OnPolicyResumeTest, PpoResumesExactly) {
  ExpectExactResume("cartpole_ppo.yaml",
                    {"experiment.steps_per_task=2500", "experiment.eval_every=500"}, "ppo");
}

TEST(OnPolicyResumeTest, TePpoResumesExactly) {
  ExpectExactResume("point_nav_teppo.yaml",
                    {"experiment.steps_per_task=2400", "experiment.eval_every=400"}, "teppo");
}

TEST(OnPolicyResumeTest, Rl2ResumesExactly) {
  // trials of 10 one-pull episodes: the checkpoint falls between trials
  ExpectExactResume("bandit_rl2.yaml",
                    {"experiment.steps_per_task=2500", "experiment.eval_every=500"}, "rl2");
}

TEST(OnPolicyResumeTest, MamlResumesExactly) {
  // the meta-test at every evaluation, the adaptation inside every iteration
  ExpectExactResume("point_nav_maml.yaml",
                    {"experiment.steps_per_task=3000", "experiment.eval_every=1000",
                     "meta_test.trials_per_task=4"},
                    "maml");
}

TEST(OnPolicyResumeTest, PearlResumesExactly) {
  // per-task RL and encoder replay, the learner's and the replay's generators
  ExpectExactResume("point_nav_pearl.yaml",
                    {"experiment.steps_per_task=1600", "experiment.eval_every=400",
                     "meta_test.trials_per_task=4", "agent.hidden_dim=32",
                     "agent.encoder_hidden_dim=32", "agent.updates_per_iteration=10"},
                    "pearl");
}

TEST(OnPolicyResumeTest, TrpoResumesExactly) {
  ExpectExactResume("point_nav_trpo.yaml",
                    {"experiment.steps_per_task=2400", "experiment.eval_every=400"}, "trpo");
}

std::string ErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(AlgorithmRegistryTest, UnknownAlgorithmsAndUnsupportedSpacesAreConfigErrors) {
  const std::string unknown = ErrorOf([] { TrainConfig::Load(std::nullopt, {"agent.algo=ppp"}); });
  EXPECT_NE(unknown.find("ppo"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("sac, ppo, trpo"), std::string::npos) << unknown;
  // SAC's keys are not PPO's
  const std::string foreign =
      ErrorOf([] { TrainConfig::Load(std::nullopt, {"agent.algo=ppo", "agent.actor_lr=1"}); });
  EXPECT_NE(foreign.find("agent.actor_lr"), std::string::npos) << foreign;
  // off-policy keys set for an on-policy algorithm would be ignored: refused
  TrainConfig ppo = TrainConfig::Load(std::nullopt, {"agent.algo=ppo", "env.id=cartpole",
                                                     "experiment.warmup_steps=10"});
  EXPECT_NE(ErrorOf([&] { ppo.Validate(); }).find("warmup_steps"), std::string::npos);
  // SAC cannot act in a Discrete env
  TrainConfig sac = TrainConfig::Load(std::nullopt, {"env.id=cartpole"});
  sac.experiment.run_dir = Scratch("sac_discrete").string();
  const std::string discrete = ErrorOf([&] { Trainer::Create(sac); });
  EXPECT_NE(discrete.find("Discrete"), std::string::npos) << discrete;
  EXPECT_NE(discrete.find("ppo"), std::string::npos) << discrete;
  // the registry lists every algorithm with its family (no count here: a new
  // row must not need an edit of this test)
  ASSERT_GE(Algorithms().size(), 7u);
  EXPECT_EQ(FindAlgorithm("pearl").family, AlgorithmFamily::kOffPolicy);
  EXPECT_EQ(FindAlgorithm("trpo").family, AlgorithmFamily::kOnPolicy);
  // every name has its own config and a builder (a short run per algorithm)
  for (const AlgorithmInfo& info : Algorithms()) {
    EXPECT_EQ(DefaultAgentConfig(info.name).algo(), info.name);
    TrainConfig c = TrainConfig::Load(
        std::nullopt, {"agent.algo=" + info.name, "env.id=point-nav", "env.num_tasks=2",
                       "experiment.steps_per_task=1000", "experiment.eval_every=0",
                       "experiment.eval_episodes=1"});
    if (info.family == AlgorithmFamily::kOffPolicy) {
      c = TrainConfig::Load(std::nullopt,
                            {"agent.algo=" + info.name, "env.id=point-nav", "env.num_tasks=2",
                             "experiment.steps_per_task=200", "experiment.warmup_steps=100",
                             "experiment.eval_every=0", "experiment.eval_episodes=1",
                             "agent.hidden_dim=16", "agent.batch_size=16"});
    }
    if (info.observations == ObservationKind::kPixels) {
      // no point-nav frames: Meta-World's reach from 16 x 16 frames, 20-step episodes
      c = TrainConfig::Load(
          std::nullopt,
          {"agent.algo=" + info.name, "env.id=reach", "+env.options.obs=pixels",
           "+env.options.pixel_width=16", "+env.options.pixel_height=16",
           "+env.options.max_episode_steps=20", "experiment.steps_per_task=60",
           "experiment.warmup_steps=30", "experiment.eval_every=0", "experiment.eval_episodes=1",
           "agent.hidden_dim=16", "agent.batch_size=16", "agent.num_conv_layers=1",
           "replay.capacity=1000"});
    }
    c.experiment.run_dir = Scratch("registry_" + info.name).string();
    c.Validate();
    EXPECT_TRUE(Trainer::Create(c).Run().finished) << info.name;
  }
  // the resolved config names its algorithm and round-trips
  const TrainConfig trpo = TrainConfig::Load(std::nullopt, {"agent.algo=trpo"});
  EXPECT_EQ(trpo.ToJson()["agent"]["algo"], "trpo");
  EXPECT_EQ(TrainConfig::FromJson(trpo.ToJson()).ToJson(), trpo.ToJson());
}

}  // namespace
}  // namespace manyworlds::experiments
