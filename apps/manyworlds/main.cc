// manyworlds: command-line access to the environments. See README.md.
#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <functional>
#include <iostream>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#include "apps/manyworlds/commands.h"
#include "manyworlds/core/error.h"
#include "manyworlds/core/memory.h"
#include "manyworlds/core/registry.h"

namespace {

// Everything printed to standard output reached it, else one line naming the error (a full
// disk, a closed pipe, /dev/full), so that `manyworlds ... > file` never exits 0 with the
// output lost.
bool StandardOutputWritten() {
  errno = 0;
  std::cout.flush();  // with stdio sync, this is stdout's fflush: it sets errno on failure
  int err = errno;
  const bool flushed = std::fflush(stdout) == 0;
  if (err == 0) err = errno;
  const bool ok = std::cout.good() && flushed && !std::ferror(stdout);
  if (!ok) {
    std::cerr << "error: cannot write standard output"
              << (err != 0 ? std::string(": ") + std::strerror(err) : std::string()) << "\n";
  }
  return ok;
}

}  // namespace

int main(int argc, char** argv) {
  namespace cli = manyworlds::cli;
  manyworlds::KeepFreedMemoryForReuse();  // before any thread or tensor exists
  // Past a file-size limit (ulimit -f) a write fails with EFBIG, which every writer reports
  // with the file's name, instead of the kernel ending the process with SIGXFSZ. (SIGPIPE
  // keeps its default: `manyworlds envs | head` ends quietly, as Unix tools do.)
  std::signal(SIGXFSZ, SIG_IGN);
  CLI::App app{"manyworlds: multi-task and meta-RL environments in C++", "manyworlds"};
  app.require_subcommand(1);
  app.footer("Run `manyworlds <command> --help` for the options of a command.");
  cli::CommandContext context;
  app.add_flag("--progress", context.progress,
               "show progress on stderr even when stderr is not a terminal");
  cli::AddEnvsCommand(app, context);
  cli::AddRolloutCommand(app, context);
  cli::AddCheckEnvCommand(app, context);
  cli::AddBenchCommand(app, context);
  cli::AddDemoCommand(app, context);
  cli::AddExportXmlCommand(app, context);
  cli::AddRenderCommand(app, context);
  cli::AddBaselinesCommand(app, context);
#ifdef MANYWORLDS_HAS_AGENTS
  cli::AddTrainCommand(app, context);
  cli::AddEvalCommand(app, context);
  cli::AddStudyCommand(app, context);
#endif

  // every failure is one line on stderr; 2 = bad usage or config, 1 = runtime
  try {
    // CLI11 would only say "a subcommand is required" for a mistyped command
    const std::function<bool(const CLI::App*)> any = [](const CLI::App*) { return true; };
    std::vector<std::string> names;
    for (const CLI::App* sub : std::as_const(app).get_subcommands(any)) {
      names.push_back(sub->get_name());
    }
    if (argc > 1 && argv[1][0] != '-' &&
        std::find(names.begin(), names.end(), argv[1]) == names.end()) {
      throw manyworlds::ConfigError("unknown command '" + std::string(argv[1]) + "'" +
                                    manyworlds::SuggestNearest(argv[1], names) +
                                    "; run `manyworlds --help` for the list");
    }
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) {  // --help
      const int code = app.exit(e);
      return StandardOutputWritten() ? code : 1;
    }
    std::cerr << "error: " << e.what() << " (see --help)\n";
    return 2;
  } catch (const manyworlds::ConfigError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    // one line: libtorch's errors carry a backtrace of 30-40 frames after their message
    const std::string what = e.what();
    std::cerr << "error: " << what.substr(0, what.find('\n')) << "\n";
    return 1;
  }
  if (!StandardOutputWritten() && context.exit_code == 0) return 1;
  return context.exit_code;
}
