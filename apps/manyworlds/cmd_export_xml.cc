// manyworlds export-xml --env ID [--task-seed T] --out FILE: the complete
// MJCF of one task variation of a MuJoCo env, loadable by MuJoCo on its own.
#include <iostream>

#include "apps/manyworlds/cli_util.h"
#include "apps/manyworlds/commands.h"
#include "manyworlds/envs/all.h"

namespace manyworlds::cli {
namespace {

struct ExportXmlArgs {
  std::string env;
  std::vector<std::string> options;
  uint64_t task_seed = 0;
  std::string out;
};

void RunExportXml(const ExportXmlArgs& args) {
  auto env = Make(args.env, ParseEnvOptions(args.options));
  env->SeedTask(args.task_seed);
  env->ResetTaskState();
  SaveTaskXml(*env, args.out);
  std::cout << args.out << ": " << env->GetTaskState().ToJson().dump() << "\n";
}

}  // namespace

void AddExportXmlCommand(CLI::App& app, CommandContext& /*context*/) {
  auto args = std::make_shared<ExportXmlArgs>();
  CLI::App* cmd = app.add_subcommand(
      "export-xml", "Write the complete MJCF of one task variation of a MuJoCo env");
  cmd->add_option("--env", args->env,
                  "env id: a MuJoCo env (a manipulation task or benchmark, "
                  "box-world-simple/-complex, half-cheetah-vel/-dir, "
                  "dmc-finger-spin/-cheetah-run/-walker-walk, the hipbmdp-* variants of those)")
      ->required();
  cmd->add_option("--task-seed", args->task_seed, "task seed: which variation is drawn")
      ->capture_default_str()
      ->check(Unsigned());
  cmd->add_option("--option", args->options, "env option key=value (repeatable)");
  cmd->add_option("--out", args->out, "output .xml file (written atomically)")->required();
  cmd->callback([args] { RunExportXml(*args); });
}

}  // namespace manyworlds::cli
