// The hostile-input probes' runner: each case in its own child process (fork, no exec), so
// that a crash, a hang or runaway memory is a finding reported with its case instead of the
// end of the test. Header-only, POSIX.
#ifndef MANYWORLDS_TESTS_SUPPORT_CHILD_CASES_H_
#define MANYWORLDS_TESTS_SUPPORT_CHILD_CASES_H_

#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace manyworlds::test_support {

#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kAddressSanitizer = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
inline constexpr bool kAddressSanitizer = true;
#else
inline constexpr bool kAddressSanitizer = false;
#endif
#else
inline constexpr bool kAddressSanitizer = false;
#endif

struct ChildLimits {
  int seconds = 60;                  // a case running longer is a hang (SIGALRM)
  unsigned long address_space_gib = 4;  // RLIMIT_AS of each child (not under ASan)
};

// Runs run(i) for i in [0, count) in child processes, as many at a time as there are cores
// (at most 4). run returns the case's verdict text (at most 1,000 characters are kept).
// The result of case i is its verdict, or, when the child did not give one, a text that
// starts with "!": "!hang: ...", "!killed by signal ...", "!exited N without a verdict".
// cpu_seconds, where given, receives each case's CPU time (user and system): where a probe's
// time goes.
inline std::vector<std::string> RunInChildren(size_t count,
                                              const std::function<std::string(size_t)>& run,
                                              ChildLimits limits = {},
                                              std::vector<double>* cpu_seconds = nullptr) {
  struct Child {
    size_t index = 0;
    int read_fd = -1;
  };
  const size_t parallel = std::clamp<size_t>(std::thread::hardware_concurrency(), 1, 4);
  std::vector<std::string> results(count);
  if (cpu_seconds != nullptr) cpu_seconds->assign(count, 0.0);
  std::map<pid_t, Child> running;
  size_t next = 0;
  while (next < count || !running.empty()) {
    while (next < count && running.size() < parallel) {
      int fds[2];
      if (pipe(fds) != 0) throw std::runtime_error("pipe failed");
      const pid_t pid = fork();
      if (pid < 0) throw std::runtime_error("fork failed");
      if (pid == 0) {
        close(fds[0]);
        alarm(static_cast<unsigned>(limits.seconds));
        if (!kAddressSanitizer) {  // ASan reserves terabytes of address space
          const rlim_t bytes = static_cast<rlim_t>(limits.address_space_gib) << 30;
          const rlimit address_space{bytes, bytes};
          setrlimit(RLIMIT_AS, &address_space);
        }
        std::string verdict = run(next);
        if (verdict.size() > 1000) verdict.resize(1000);
        const ssize_t written = write(fds[1], verdict.data(), verdict.size());
        _exit(written == static_cast<ssize_t>(verdict.size()) ? 0 : 3);
      }
      close(fds[1]);
      running[pid] = {next, fds[0]};
      ++next;
    }
    int status = 0;
    rusage usage{};
    const pid_t done = wait4(-1, &status, 0, &usage);
    if (done <= 0) throw std::runtime_error("wait4 failed");
    const auto it = running.find(done);
    if (it == running.end()) continue;  // not one of ours
    if (cpu_seconds != nullptr) {
      auto seconds = [](const timeval& t) { return t.tv_sec + t.tv_usec * 1e-6; };
      (*cpu_seconds)[it->second.index] = seconds(usage.ru_utime) + seconds(usage.ru_stime);
    }
    std::string text;
    char buffer[1024];
    for (ssize_t n; (n = read(it->second.read_fd, buffer, sizeof(buffer))) > 0;) {
      text.append(buffer, static_cast<size_t>(n));
    }
    close(it->second.read_fd);
    std::string& result = results[it->second.index];
    if (WIFSIGNALED(status)) {
      result = WTERMSIG(status) == SIGALRM
                   ? "!hang: still running after " + std::to_string(limits.seconds) + " s"
                   : std::string("!killed by signal ") + strsignal(WTERMSIG(status));
    } else if (WEXITSTATUS(status) != 0 || text.empty()) {
      result = "!exited " + std::to_string(WEXITSTATUS(status)) +
               " without a verdict (an abort or exit inside the case?)";
    } else {
      result = std::move(text);
    }
    running.erase(it);
  }
  return results;
}

// Whether an error message is the one line of bounded length a user should get.
inline std::string ProblemWithMessage(const std::string& message, size_t max_chars = 600) {
  if (message.find('\n') != std::string::npos) return "a multi-line error: " + message;
  if (message.size() > max_chars) {
    return "an error of " + std::to_string(message.size()) + " characters: " +
           message.substr(0, 200);
  }
  if (message.empty()) return "an empty error message";
  return "";
}

}  // namespace manyworlds::test_support

#endif  // MANYWORLDS_TESTS_SUPPORT_CHILD_CASES_H_
