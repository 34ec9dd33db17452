// check-env on every registered env, benchmarks included: the slowest CLI
// test (about 45 s on two cores), in a file of its own so that the quick suite
// (ctest -LE slow) can leave it out.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <filesystem>
#include <string>

#include "tests/support/cli_runner.h"

namespace manyworlds {
namespace {

using test_support::RunResult;

RunResult RunCli(const std::string& args) {
  return test_support::RunProgram(MANYWORLDS_CLI_PATH, args,
                                  std::filesystem::temp_directory_path());
}

TEST(CliTest, CheckEnvPassesOnEveryRegisteredEnv) {
  const RunResult list = RunCli("envs --json");
  ASSERT_EQ(list.exit_code, 0) << list.err;
  const auto envs = nlohmann::json::parse(list.out);
  ASSERT_GE(envs.size(), 7u);
  for (const auto& e : envs) {
    const std::string id = e["id"];
    const RunResult r = RunCli("check-env --env " + id);
    EXPECT_EQ(r.exit_code, 0) << id << "\n" << r.out << r.err;
  }
}

}  // namespace
}  // namespace manyworlds
