// Runs the built `manyworlds` program from a test, as a user would, and
// captures what it printed. Shared by the CLI tests of every layer.
#ifndef MANYWORLDS_TESTS_SUPPORT_CLI_RUNNER_H_
#define MANYWORLDS_TESTS_SUPPORT_CLI_RUNNER_H_

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace manyworlds::test_support {

struct RunResult {
  int exit_code = -1;  // -1 when the program did not exit normally
  std::string out;     // stdout
  std::string err;     // stderr
};

inline std::string Slurp(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Runs `<cli> <args>` through the shell in `cwd`, stdout and stderr captured
// separately. stderr goes through a file named after this process, since
// ctest -j runs test processes side by side.
inline RunResult RunProgram(const std::string& cli, const std::string& args,
                            const std::filesystem::path& cwd) {
  const std::filesystem::path err_file =
      std::filesystem::temp_directory_path() /
      ("manyworlds_cli_stderr_" + std::to_string(getpid()) + ".txt");
  const std::string command =
      "cd '" + cwd.string() + "' && '" + cli + "' " + args + " 2>'" + err_file.string() + "'";
  RunResult result;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return result;
  char buffer[4096];
  size_t n;
  while ((n = fread(buffer, 1, sizeof(buffer), pipe)) > 0) result.out.append(buffer, n);
  const int status = pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  result.err = Slurp(err_file);
  std::filesystem::remove(err_file);
  return result;
}

// The program's contract for bad input: exactly one line, "error: ...".
inline bool IsOneErrorLine(const std::string& err) {
  return err.rfind("error: ", 0) == 0 && err.find('\n') == err.size() - 1;
}

}  // namespace manyworlds::test_support

#endif  // MANYWORLDS_TESTS_SUPPORT_CLI_RUNNER_H_
