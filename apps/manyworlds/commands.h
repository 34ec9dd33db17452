// The subcommands of the `manyworlds` program, one .cc file each.
//
// Each Add*Command registers a CLI11 subcommand whose callback does the
// work. Callbacks report bad input by throwing ConfigError (exit code 2) and
// runtime failures by throwing Error (exit code 1); a command that ran but
// found problems (check-env) sets context.exit_code.
#ifndef APPS_MANYWORLDS_COMMANDS_H_
#define APPS_MANYWORLDS_COMMANDS_H_

#include <cstdint>
#include <string>

#include <CLI/CLI.hpp>

namespace manyworlds::cli {

struct CommandContext {
  int exit_code = 0;
  bool progress = false;  // --progress: show progress even if stderr is not a TTY
};

void AddEnvsCommand(CLI::App& app, CommandContext& context);
void AddRolloutCommand(CLI::App& app, CommandContext& context);
void AddCheckEnvCommand(CLI::App& app, CommandContext& context);
void AddBenchCommand(CLI::App& app, CommandContext& context);
void AddDemoCommand(CLI::App& app, CommandContext& context);
void AddExportXmlCommand(CLI::App& app, CommandContext& context);
void AddRenderCommand(CLI::App& app, CommandContext& context);
void AddBaselinesCommand(CLI::App& app, CommandContext& context);

// Commands that need libtorch live in torch_*.cc files, built only when the
// agents layer is (MANYWORLDS_HAS_AGENTS).
void AddTrainCommand(CLI::App& app, CommandContext& context);
void AddEvalCommand(CLI::App& app, CommandContext& context);
// `study boxworld`: the CS330 box-world study (torch_study.cc).
void AddStudyCommand(CLI::App& app, CommandContext& context);
// `rollout --policy checkpoint:PATH`: seeded episodes of a trained run's
// policy (PATH a run directory or one of its checkpoints) on every task of
// the run; env_id, if not empty, must be the run's env.
void RunCheckpointRollout(const std::string& path, const std::string& env_id, int episodes,
                          uint64_t seed, bool json);
// `bench agent`, added under the `bench` command.
void AddBenchAgentSubcommand(CLI::App& bench, CommandContext& context);
// `bench collect`, likewise.
void AddBenchCollectSubcommand(CLI::App& bench, CommandContext& context);

}  // namespace manyworlds::cli

#endif  // APPS_MANYWORLDS_COMMANDS_H_
