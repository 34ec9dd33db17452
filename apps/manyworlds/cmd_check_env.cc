// manyworlds check-env --env ID: the CheckEnv report; exit 1 if a check fails.
#include <iostream>

#include "apps/manyworlds/cli_util.h"
#include "apps/manyworlds/commands.h"
#include "manyworlds/core/env_checker.h"
#include "manyworlds/envs/all.h"

namespace manyworlds::cli {
namespace {

struct CheckEnvArgs {
  std::string env;
  std::vector<std::string> options;
  bool json = false;
};

int RunCheckEnv(const CheckEnvArgs& args) {
  const nlohmann::json options = ParseEnvOptions(args.options);
  // build one env up front so that a bad id or option is a usage error, not a failed check
  Make(args.env, options);
  const CheckReport report = CheckEnv([&] { return Make(args.env, options); });
  if (args.json) {
    PrintJson(report.ToJson());
  } else {
    int passed = 0;
    for (const auto& check : report.checks) passed += check.passed ? 1 : 0;
    const std::string text = report.ToString();
    std::cout << text;
    if (!text.empty() && text.back() != '\n') std::cout << "\n";
    std::cout << args.env << ": " << passed << "/" << report.checks.size() << " checks passed\n";
  }
  return report.ok() ? 0 : 1;
}

}  // namespace

void AddCheckEnvCommand(CLI::App& app, CommandContext& context) {
  auto args = std::make_shared<CheckEnvArgs>();
  CLI::App* cmd = app.add_subcommand(
      "check-env", "Check an env against the API contract (determinism, spaces, errors)");
  cmd->add_option("--env", args->env, "env id (see `manyworlds envs`)")->required();
  cmd->add_option("--option", args->options, "env option key=value (repeatable)");
  cmd->add_flag("--json", args->json, "print the report as JSON");
  cmd->callback([args, &context] { context.exit_code = RunCheckEnv(*args); });
}

}  // namespace manyworlds::cli
