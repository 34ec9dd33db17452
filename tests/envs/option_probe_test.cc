// The hostile-option probe: every option of every registered env id, given each value of a
// fixed table of hostile values (non-finite and huge numbers, integers past int64, nested and
// enormous strings, wrong types). Each case runs in a child process
// (tests/support/child_cases.h). A case passes when the registry refuses the value with a
// one-line ConfigError of bounded length, or when it accepts it and the env then resets and
// steps with finite observations and rewards.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <new>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "manyworlds/core/error.h"
#include "manyworlds/core/policy.h"
#include "manyworlds/envs/all.h"
#include "tests/support/child_cases.h"

namespace manyworlds {
namespace {

constexpr int kSteps = 20;  // steps of an accepted case

struct HostileValue {
  std::string label;
  nlohmann::json value;
};

// The same table for every option: as command-line strings (what `--option k=v` and a YAML
// config hand the registry) and as typed values (what Python and the C++ API hand it).
std::vector<HostileValue> HostileValues() {
  std::vector<HostileValue> values;
  for (const char* text :
       {"nan", "inf", "-inf", "1e308", "-1e308", "1e-320", "-1", "0", "9223372036854775807",
        "-9223372036854775808", "18446744073709551616", "", "[[[", "{\"a\": 1}", "true", " 5",
        "0x10", "1e9"}) {
    values.push_back({std::string("'") + text + "'", text});
  }
  values.push_back({"60,000 nested '['", std::string(60000, '[') + std::string(60000, ']')});
  values.push_back({"a string of 100,000 x", std::string(100000, 'x')});
  values.push_back({"null", nullptr});
  values.push_back({"NaN (number)", std::nan("")});
  values.push_back({"inf (number)", std::numeric_limits<double>::infinity()});
  values.push_back({"1e308 (number)", 1e308});
  values.push_back({"-1e308 (number)", -1e308});
  values.push_back({"2^63-1 (number)", std::numeric_limits<int64_t>::max()});
  values.push_back({"-2^63 (number)", std::numeric_limits<int64_t>::min()});
  values.push_back({"2^64-1 (number)", std::numeric_limits<uint64_t>::max()});
  values.push_back({"1e9 (number)", int64_t{1000000000}});
  values.push_back({"[1] (list)", nlohmann::json::array({1})});
  values.push_back({"{} (mapping)", nlohmann::json::object()});
  values.push_back({"true (bool)", true});
  return values;
}

struct Case {
  std::string id;
  std::string option;
  const HostileValue* value;
};

void CheckFinite(std::span<const float> values, const std::string& what) {
  for (size_t i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i])) {
      throw std::runtime_error(what + " element " + std::to_string(i) + " is " +
                               std::to_string(values[i]));
    }
  }
}

// Options that act only beside another one: probed with it on, so that their value is used.
nlohmann::json CompanionOptions(const std::string& option) {
  if (option == Registry::kRecurrentMetaObsScaleOption) {
    return {{std::string(Registry::kRecurrentMetaObsOption), true}};
  }
  if (option == Registry::kPixelWidthOption || option == Registry::kPixelHeightOption ||
      option == Registry::kCameraOption || option == Registry::kPixelQualityOption) {
    return {{std::string(Registry::kObsOption), "pixels"}};
  }
  return nlohmann::json::object();
}

// In the child: "R<message>" refused, "A" accepted and stepped, "F<why>" failed.
std::string RunCase(const Case& c) {
  std::unique_ptr<Env> env;
  try {
    nlohmann::json options = CompanionOptions(c.option);
    options[c.option] = c.value->value;
    env = DefaultRegistry().Make(c.id, options);
  } catch (const ConfigError& e) {
    const std::string problem = test_support::ProblemWithMessage(e.what());
    return problem.empty() ? std::string("R") + e.what() : "F" + problem;
  } catch (const std::bad_alloc&) {
    return "Fout of memory while making the env (no estimate refused it first)";
  } catch (const std::exception& e) {
    return std::string("Fnot a ConfigError: ") + e.what();
  }
  try {
    RandomPolicy policy(env->spec().action_space, 3);
    env->SeedTask(7);
    env->ResetTaskState();
    env->Seed(7);
    Observation obs = env->Reset();
    CheckFinite(obs.env_obs, "reset env_obs");
    CheckFinite(obs.task_obs, "reset task_obs");
    std::vector<float> action(static_cast<size_t>(env->spec().action_space.flat_size()));
    for (int t = 0; t < kSteps; ++t) {
      policy.Act(obs.env_obs, obs.task_obs, action);
      StepResult step = env->Step(action);
      CheckFinite(step.obs.env_obs, "step " + std::to_string(t) + " env_obs");
      CheckFinite(step.obs.task_obs, "step " + std::to_string(t) + " task_obs");
      if (!std::isfinite(step.reward)) {
        throw std::runtime_error("step " + std::to_string(t) + " reward is " +
                                 std::to_string(step.reward));
      }
      obs = step.terminated || step.truncated ? env->Reset() : std::move(step.obs);
    }
  } catch (const std::bad_alloc&) {
    return "Fout of memory while stepping";
  } catch (const std::exception& e) {
    return std::string("Faccepted, then: ") + e.what();
  }
  return "A";
}

TEST(OptionProbeTest, EveryOptionOfEveryEnvTakesHostileValuesWithoutHarm) {
  const Registry& registry = DefaultRegistry();  // built before the children fork
  const std::vector<HostileValue> values = HostileValues();
  std::vector<Case> cases;
  // The registry's own options (the same code for every env) on the first env of each family;
  // every env's own options on every env.
  const auto& reserved = Registry::ReservedOptions();
  std::set<std::string> families;
  for (const EnvRegistration& entry : registry.entries()) {
    const bool first_of_family = families.insert(entry.family).second;
    for (const OptionSpec& option : entry.options) {
      const bool is_reserved =
          std::find(reserved.begin(), reserved.end(), option.name) != reserved.end();
      if (is_reserved && !first_of_family) continue;
      for (const HostileValue& value : values) cases.push_back({entry.id, option.name, &value});
    }
  }
  const auto start = std::chrono::steady_clock::now();
  const std::vector<std::string> verdicts =
      test_support::RunInChildren(cases.size(), [&](size_t i) { return RunCase(cases[i]); });
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  size_t refused = 0, accepted = 0, failed = 0;
  std::string failures;
  for (size_t i = 0; i < cases.size(); ++i) {
    const std::string& verdict = verdicts[i];
    if (verdict[0] == 'R') {
      ++refused;
    } else if (verdict == "A") {
      ++accepted;
    } else if (++failed <= 60) {
      failures += "\n  " + cases[i].id + " " + cases[i].option + "=" + cases[i].value->label +
                  ": " + verdict.substr(1);
    }
  }
  std::printf("option probe: %zu cases (%zu env ids, %zu hostile values per option) in %.1f s: "
              "%zu refused with one line, %zu accepted and stepped, %zu failed\n",
              cases.size(), registry.entries().size(), values.size(), seconds, refused, accepted,
              failed);
  RecordProperty("cases", static_cast<int>(cases.size()));
  EXPECT_EQ(failed, 0u) << failed << " cases failed (the first 60):" << failures;
  // the table is not vacuous: every env has options, and most hostile values are refused
  EXPECT_GT(cases.size(), 10000u);
  EXPECT_GT(refused, accepted);
}

}  // namespace
}  // namespace manyworlds
