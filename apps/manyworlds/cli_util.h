// Helpers shared by the subcommands: option parsing, tables, number
// formatting, a progress bar and the seeded random-policy rollout.
#ifndef APPS_MANYWORLDS_CLI_UTIL_H_
#define APPS_MANYWORLDS_CLI_UTIL_H_

#include <chrono>
#include <cstdint>
#include <iosfwd>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "apps/manyworlds/remaining_time.h"
#include "manyworlds/core/env.h"
#include "manyworlds/core/policy.h"
#include "manyworlds/envs/all.h"

namespace manyworlds::cli {

// {"key": "value", ...} from "key=value" strings (the registry converts the
// strings to each option's type). Throws ConfigError on a malformed or
// repeated key.
nlohmann::json ParseEnvOptions(const std::vector<std::string>& pairs);

// Accepts integers in [1, max] ("--episodes: must be an integer in [1, 1000000], got 0");
// the bound keeps counts far from overflow and sizes within memory.
CLI::Validator AtLeastOne(int64_t max = 1000000000);
// Accepts integers in [0, 2^64) (CLI11 would wrap "-1" to 2^64 - 1).
CLI::Validator Unsigned();

// The policies the CLI can build: PolicyNames, CheckPolicyName, MakePolicy
// (envs/all.h).

// The CLI's seeding protocol. Every episode is seeded from its index alone,
// so that episodes can run on any number of threads with the same results:
// episode i runs with env seed MixSeed(seed, i), task seed task_seed, and
// the named policy seeded from MixSeed(MixSeed(seed, kPolicySeedStream), i).
// SeedEpisode does that to `env` and returns the policy; the caller then
// sets the task (ResetTaskState, or a given task state).
inline constexpr uint64_t kPolicySeedStream = 0x706f6c696379;  // "policy"
std::unique_ptr<Policy> SeedEpisode(Env& env, std::string_view policy, uint64_t seed,
                                    uint64_t task_seed, int episode);
// `episodes` episodes of the task sampled from task_seed (one
// ResetTaskState per episode, the same task each time), on `threads`
// threads; threads > 1 needs make_env for the other threads' envs. Same
// arguments, same summary, whatever the thread count.
RolloutSummary SeededRollout(Env& env, std::string_view policy, uint64_t seed, uint64_t task_seed,
                             int episodes, int threads = 1, const EnvMaker& make_env = {});

// "12.35" with `digits` decimals.
std::string Fixed(double value, int digits);
// "1.23M", "45.6k", "789": three significant digits.
std::string Human(double value);
// "0.40", or "-" for a negative rate (env reports no success).
std::string SuccessRate(double rate);
// Prints "<text>\n" on stdout (for --json output).
void PrintJson(const nlohmann::json& json);

// A plain text table with aligned columns.
class Table {
 public:
  // Columns whose header starts with '>' are right-aligned (the '>' is dropped).
  explicit Table(std::vector<std::string> headers);
  void AddRow(std::vector<std::string> cells);
  void Print(std::ostream& out) const;

 private:
  std::vector<std::string> headers_;
  std::vector<bool> right_;
  std::vector<std::vector<std::string>> rows_;
};

// "[#####.....]": a bar `width` characters wide, filled to `fraction` (clamped to [0, 1]).
std::string Bar(double fraction, int width = 20);

// One status line on stderr: redrawn in place on a terminal, one printed
// line per Write otherwise. Note prints a line that stays. Clears itself
// when destroyed.
class StatusLine {
 public:
  StatusLine();
  ~StatusLine();
  StatusLine(const StatusLine&) = delete;
  StatusLine& operator=(const StatusLine&) = delete;

  bool tty() const { return tty_; }
  void Write(const std::string& line);
  void Note(const std::string& text);
  void Clear();

 private:
  bool tty_;
  bool drawn_ = false;
};

// "label 3/7 envs [#####....] 1.2 envs/s ETA 4s" on stderr, redrawn in place
// on a terminal (at most 10 times a second); with force on a non-terminal,
// one line per second. Silent otherwise. Clears itself when destroyed.
class ProgressBar {
 public:
  ProgressBar(std::string label, int64_t total, std::string unit, bool force);
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  void Advance(int64_t count = 1);

 private:
  void Draw(bool final);

  using Clock = std::chrono::steady_clock;
  std::string label_, unit_;
  int64_t total_, done_ = 0;
  bool enabled_, tty_;
  Clock::time_point start_, last_draw_;
  RemainingTime remaining_;
};

}  // namespace manyworlds::cli

#endif  // APPS_MANYWORLDS_CLI_UTIL_H_
