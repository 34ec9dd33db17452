#include "manyworlds/core/env_checker.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "manyworlds/core/error.h"
#include "manyworlds/core/wrappers.h"
#include "tests/core/toy_env.h"

namespace manyworlds {
namespace {

using testing::ToyEnv;

const std::vector<std::string> kCheckNames = {
    "make-env",
    "spaces-well-formed",
    "info-fields-unique",
    "same-seeds-identical-trajectories",
    "different-env-seeds-differ",
    "different-task-seeds-differ",
    "observations-in-space",
    "rewards-and-info-finite",
    "task-state-round-trip",
    "task-state-reproduces-trajectory",
    "foreign-task-state-rejected",
    "malformed-task-state-rejected",
    "step-before-reset-raises",
    "step-after-end-raises",
    "wrong-action-length-raises",
    "non-finite-action-raises",
    "discrete-action-out-of-space-raises",
    "box-action-clipped",
};

const CheckResult* Find(const CheckReport& report, const std::string& name) {
  for (const auto& check : report.checks) {
    if (check.name == name) return &check;
  }
  return nullptr;
}

std::vector<std::string> Failed(const CheckReport& report) {
  std::vector<std::string> names;
  for (const auto& check : report.checks) {
    if (!check.passed) names.push_back(check.name);
  }
  return names;
}

std::unique_ptr<Env> Toy(bool discrete = false) { return std::make_unique<ToyEnv>(discrete); }

TEST(EnvCheckerTest, ToyEnvPassesEveryCheckInBothVariants) {
  for (bool discrete : {false, true}) {
    const CheckReport report = CheckEnv([&] { return Toy(discrete); });
    EXPECT_TRUE(report.ok()) << report.ToString();
    EXPECT_EQ(report.env_id, discrete ? "toy-discrete" : "toy");
    std::vector<std::string> names;
    for (const auto& check : report.checks) names.push_back(check.name);
    EXPECT_EQ(names, kCheckNames);
  }
}

TEST(EnvCheckerTest, WrappedToyEnvsPassEveryCheck) {
  const std::vector<std::function<std::unique_ptr<Env>()>> factories = {
      [] { return std::make_unique<NTasks>(Toy(), 5); },
      [] { return std::make_unique<NTasksId>(Toy(), 5); },
      [] { return std::make_unique<NTasksId>(Toy(true), 4, TaskIdEncoding::kOneHot); },
      [] { return std::make_unique<SampleRandomTask>(Toy()); },
      [] { return std::make_unique<TimeLimit>(Toy(true), 20); },
      [] {
        std::vector<std::unique_ptr<Env>> envs;
        envs.push_back(Toy());
        envs.push_back(std::make_unique<NTasks>(Toy(), 3));
        return std::make_unique<MultiEnv>(std::move(envs));
      },
      [] { return std::make_unique<AppendTaskOneHot>(std::make_unique<NTasksId>(Toy(), 3)); },
      [] {
        std::vector<std::unique_ptr<Env>> envs;
        for (int i = 0; i < 3; ++i) envs.push_back(Toy(true));
        return std::make_unique<AppendTaskOneHot>(
            std::make_unique<SampleRandomTask>(std::make_unique<MultiEnv>(std::move(envs))));
      },
  };
  for (const auto& factory : factories) {
    const CheckReport report = CheckEnv(factory, {.steps = 150});
    EXPECT_TRUE(report.ok()) << report.env_id << "\n" << report.ToString();
  }
}

// Uses a process-wide counter, so two instances with the same seeds differ.
class UnseededEnv : public ToyEnv {
 protected:
  void DoReset(const ObsView& out) override {
    static int counter = 0;
    ToyEnv::DoReset(out);
    out.env_obs[1] = 0.001f * static_cast<float>(++counter);
  }
};

// Declares Box(-1, 1) observations but reports a velocity of 2.
class OutOfSpaceEnv : public ToyEnv {
 public:
  OutOfSpaceEnv() { mutable_spec().env_obs_space = Space::Box(-1.0f, 1.0f, {2}); }

 protected:
  void DoStep(std::span<const float> action, const StepView& out) override {
    ToyEnv::DoStep(action, out);
    out.env_obs[1] = 2.0f;
  }
};

// Reports its target rounded to float, so GetTaskState differs from the
// state that was set.
class LossyTaskStateEnv : public ToyEnv {
 protected:
  TaskState DoGetTaskState() const override {
    return TaskState{id(), {{"target", static_cast<double>(static_cast<float>(target()))}}};
  }
};

// Reads task states without validation: accepts foreign states and lets
// nlohmann's type errors escape on malformed ones.
class LaxTaskStateEnv : public ToyEnv {
 protected:
  void DoSetTaskState(const TaskState& state) override {
    const double target = state.params.at("target").get<double>();
    ToyEnv::DoSetTaskState(TaskState{id(), {{"target", target}}});
  }
};

// Ignores the set task and keeps the first one it was given.
class StickyTaskEnv : public ToyEnv {
 protected:
  TaskState DoGetTaskState() const override { return last_set_; }
  void DoSetTaskState(const TaskState& state) override {
    TaskStateReader(state, id()).Number("target", -1.0, 1.0);
    if (!applied_) ToyEnv::DoSetTaskState(state);
    applied_ = true;
    last_set_ = state;
  }

 private:
  bool applied_ = false;
  TaskState last_set_;
};

// Throws a plain runtime_error from its dynamics.
class ThrowingEnv : public ToyEnv {
 protected:
  void DoStep(std::span<const float>, const StepView&) override {
    throw std::runtime_error("simulated crash");
  }
};

template <typename E>
CheckReport CheckBroken() {
  return CheckEnv([] { return std::make_unique<E>(); }, {.steps = 100});
}

TEST(EnvCheckerTest, UnseededRandomnessFailsTheSameSeedsCheck) {
  const CheckReport report = CheckBroken<UnseededEnv>();
  EXPECT_FALSE(report.ok());
  EXPECT_FALSE(Find(report, "same-seeds-identical-trajectories")->passed) << report.ToString();
  EXPECT_TRUE(Find(report, "observations-in-space")->passed);
}

TEST(EnvCheckerTest, ObservationsOutsideTheSpaceFailTheSpaceCheck) {
  const CheckReport report = CheckBroken<OutOfSpaceEnv>();
  const CheckResult* check = Find(report, "observations-in-space");
  EXPECT_FALSE(check->passed);
  EXPECT_NE(check->message.find("env_obs"), std::string::npos) << check->message;
  EXPECT_EQ(Failed(report), std::vector<std::string>{"observations-in-space"}) << report.ToString();
}

TEST(EnvCheckerTest, ATaskStateThatDoesNotRoundTripFails) {
  const CheckReport report = CheckBroken<LossyTaskStateEnv>();
  EXPECT_FALSE(Find(report, "task-state-round-trip")->passed) << report.ToString();
  EXPECT_TRUE(Find(report, "same-seeds-identical-trajectories")->passed);
}

TEST(EnvCheckerTest, UnvalidatedTaskStatesFailTheRejectionChecks) {
  const CheckReport report = CheckBroken<LaxTaskStateEnv>();
  EXPECT_EQ(Failed(report), (std::vector<std::string>{"foreign-task-state-rejected",
                                                      "malformed-task-state-rejected"}))
      << report.ToString();
  EXPECT_NE(
      Find(report, "malformed-task-state-rejected")->message.find("instead of TaskStateError"),
      std::string::npos);
}

TEST(EnvCheckerTest, AnIgnoredTaskStateFailsTheReproductionCheck) {
  const CheckReport report = CheckBroken<StickyTaskEnv>();
  EXPECT_FALSE(Find(report, "task-state-reproduces-trajectory")->passed) << report.ToString();
}

TEST(EnvCheckerTest, NeverThrowsForAFailingEnv) {
  CheckReport report;
  ASSERT_NO_THROW(report = CheckBroken<ThrowingEnv>());
  EXPECT_FALSE(report.ok());
  const CheckResult* check = Find(report, "same-seeds-identical-trajectories");
  EXPECT_FALSE(check->passed);
  EXPECT_NE(check->message.find("simulated crash"), std::string::npos) << check->message;
  EXPECT_TRUE(Find(report, "spaces-well-formed")->passed);

  ASSERT_NO_THROW(report = CheckEnv([] { return std::unique_ptr<Env>(); }));
  ASSERT_EQ(report.checks.size(), 1u);
  EXPECT_FALSE(report.ok());
  ASSERT_NO_THROW(report = CheckEnv([]() -> std::unique_ptr<Env> { throw ConfigError("nope"); }));
  EXPECT_FALSE(report.ok());
}

TEST(EnvCheckerTest, ReportFormats) {
  const CheckReport report = CheckEnv([] { return Toy(); }, {.steps = 20});
  const std::string text = report.ToString();
  EXPECT_EQ(text.rfind("[PASS] make-env: ", 0), 0u) << text;
  const nlohmann::json json = report.ToJson();
  EXPECT_EQ(json["env_id"], "toy");
  EXPECT_EQ(json["ok"], true);
  EXPECT_EQ(json["checks"].size(), kCheckNames.size());
  EXPECT_EQ(json["checks"][0]["name"], "make-env");
}

}  // namespace
}  // namespace manyworlds
