#include "apps/manyworlds/cli_util.h"

#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <iostream>

#include "manyworlds/core/error.h"
#include "manyworlds/core/registry.h"
#include "manyworlds/core/rng.h"
#include "manyworlds/envs/all.h"

namespace manyworlds::cli {

nlohmann::json ParseEnvOptions(const std::vector<std::string>& pairs) {
  nlohmann::json options = nlohmann::json::object();
  for (const auto& pair : pairs) {
    const size_t eq = pair.find('=');
    if (eq == std::string::npos || eq == 0) {
      throw ConfigError("--option '" + pair +
                        "' is not of the form key=value (e.g. hide_task=true)");
    }
    const std::string key = pair.substr(0, eq);
    if (options.contains(key)) throw ConfigError("--option '" + key + "' is given twice");
    options[key] = pair.substr(eq + 1);
  }
  return options;
}

CLI::Validator AtLeastOne(int64_t max) {
  return CLI::Validator(
      [max](std::string& input) -> std::string {
        int64_t value = 0;
        const auto [end, ec] = std::from_chars(input.data(), input.data() + input.size(), value);
        if (ec != std::errc() || end != input.data() + input.size() || value < 1 || value > max) {
          const std::string shown = input.size() <= 30 ? input : input.substr(0, 20) + "...";
          return "must be an integer in [1, " + std::to_string(max) + "], got " + shown;
        }
        return "";
      },
      "");
}

CLI::Validator Unsigned() {
  return CLI::Validator(
      [](std::string& input) -> std::string {
        uint64_t value = 0;
        const auto [end, ec] = std::from_chars(input.data(), input.data() + input.size(), value);
        if (ec != std::errc() || end != input.data() + input.size()) {
          return "must be an integer in [0, 2^64), got " + input;
        }
        return "";
      },
      "");
}

std::unique_ptr<Policy> SeedEpisode(Env& env, std::string_view policy, uint64_t seed,
                                    uint64_t task_seed, int episode) {
  const uint64_t index = static_cast<uint64_t>(episode);
  env.Seed(MixSeed(seed, index));
  env.SeedTask(task_seed);
  return MakePolicy(policy, env, MixSeed(MixSeed(seed, kPolicySeedStream), index));
}

RolloutSummary SeededRollout(Env& env, std::string_view policy, uint64_t seed, uint64_t task_seed,
                             int episodes, int threads, const EnvMaker& make_env) {
  const std::string name(policy);
  return Summarize(RunEpisodes(env, make_env, episodes, threads, [&](Env& e, int i) {
    std::unique_ptr<Policy> p = SeedEpisode(e, name, seed, task_seed, i);
    e.ResetTaskState();
    return p;
  }));
}

std::string Fixed(double value, int digits) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.*f", digits, value);
  return buffer;
}

std::string Human(double value) {
  const char* suffix = "";
  if (std::abs(value) >= 1e9) {
    value /= 1e9;
    suffix = "G";
  } else if (std::abs(value) >= 1e6) {
    value /= 1e6;
    suffix = "M";
  } else if (std::abs(value) >= 1e3) {
    value /= 1e3;
    suffix = "k";
  }
  const int digits = std::abs(value) >= 100 ? 0 : std::abs(value) >= 10 ? 1 : 2;
  return Fixed(value, digits) + suffix;
}

std::string SuccessRate(double rate) { return rate < 0 ? "-" : Fixed(rate, 2); }

void PrintJson(const nlohmann::json& json) { std::cout << json.dump(2) << "\n"; }

Table::Table(std::vector<std::string> headers) {
  for (auto& h : headers) {
    right_.push_back(!h.empty() && h[0] == '>');
    headers_.push_back(right_.back() ? h.substr(1) : h);
  }
}

void Table::AddRow(std::vector<std::string> cells) {
  cells.resize(headers_.size());
  rows_.push_back(std::move(cells));
}

void Table::Print(std::ostream& out) const {
  std::vector<size_t> width(headers_.size());
  for (size_t c = 0; c < headers_.size(); ++c) {
    width[c] = headers_[c].size();
    for (const auto& row : rows_) width[c] = std::max(width[c], row[c].size());
  }
  auto line = [&](const std::vector<std::string>& cells) {
    std::string text;
    for (size_t c = 0; c < cells.size(); ++c) {
      const std::string pad(width[c] - cells[c].size(), ' ');
      const bool last = c + 1 == cells.size();
      text += right_[c] ? pad + cells[c] : cells[c] + (last ? "" : pad);
      if (!last) text += "  ";
    }
    out << text << "\n";
  };
  line(headers_);
  std::vector<std::string> rule;
  for (size_t w : width) rule.emplace_back(w, '-');
  line(rule);
  for (const auto& row : rows_) line(row);
}

ProgressBar::ProgressBar(std::string label, int64_t total, std::string unit, bool force)
    : label_(std::move(label)),
      unit_(std::move(unit)),
      total_(total),
      tty_(isatty(STDERR_FILENO) != 0),
      start_(Clock::now()),
      last_draw_(start_) {
  enabled_ = tty_ || force;
  remaining_.Update(0, static_cast<double>(total_), start_);
}

ProgressBar::~ProgressBar() {
  if (!enabled_) return;
  if (tty_) {
    std::cerr << "\r\033[K" << std::flush;
  } else if (done_ < total_) {
    Draw(true);  // an interrupted run still says how far it got
  }
}

void ProgressBar::Advance(int64_t count) {
  done_ += count;
  if (!enabled_) return;
  const auto now = Clock::now();
  const auto interval = tty_ ? std::chrono::milliseconds(100) : std::chrono::milliseconds(1000);
  if (done_ >= total_ || now - last_draw_ >= interval) {
    last_draw_ = now;
    Draw(done_ >= total_);
  }
}

std::string Bar(double fraction, int width) {
  const int filled = static_cast<int>(std::clamp(fraction, 0.0, 1.0) * width);
  return "[" + std::string(filled, '#') + std::string(width - filled, '.') + "]";
}

StatusLine::StatusLine() : tty_(isatty(STDERR_FILENO) != 0) {}

StatusLine::~StatusLine() { Clear(); }

void StatusLine::Write(const std::string& line) {
  if (tty_) {
    std::cerr << "\r" << line << "\033[K" << std::flush;
    drawn_ = true;
  } else {
    std::cerr << line << "\n";
  }
}

void StatusLine::Note(const std::string& text) {
  Clear();
  std::cerr << text << "\n";
}

void StatusLine::Clear() {
  if (tty_ && drawn_) std::cerr << "\r\033[K" << std::flush;
  drawn_ = false;
}

void ProgressBar::Draw(bool final) {
  const auto now = Clock::now();
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double rate = elapsed > 0 ? static_cast<double>(done_) / elapsed : 0.0;
  const double fraction = total_ > 0 ? std::min(1.0, static_cast<double>(done_) / total_) : 1.0;
  std::string text = label_ + " " + std::to_string(done_) + "/" + std::to_string(total_) + " " +
                     unit_ + " " + Bar(fraction, 24) + " " + Human(rate) + " " + unit_ + "/s";
  const double eta =
      remaining_.Update(static_cast<double>(done_), static_cast<double>(total_), now);
  if (!final && eta >= 0) text += " ETA " + FormatDuration(eta);
  if (tty_) {
    std::cerr << "\r\033[K" << text << std::flush;
  } else {
    std::cerr << text << "\n";
  }
}

}  // namespace manyworlds::cli
