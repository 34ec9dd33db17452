// Time left for the progress lines of `train`, `study` and the progress bar:
// estimated from the rate of the last minute, and printed as "1h05m".
#ifndef APPS_MANYWORLDS_REMAINING_TIME_H_
#define APPS_MANYWORLDS_REMAINING_TIME_H_

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <deque>
#include <string>
#include <utility>

namespace manyworlds::cli {

// "1h05m", "4m09s", "7s"; "?" for a negative, NaN or absurd (> 10^7 s) time.
inline std::string FormatDuration(double seconds) {
  if (!(seconds >= 0) || seconds > 1e7) return "?";
  const auto s = static_cast<long long>(seconds + 0.5);
  char text[32];
  if (s >= 3600) {
    std::snprintf(text, sizeof(text), "%lldh%02lldm", s / 3600, s % 3600 / 60);
  } else if (s >= 60) {
    std::snprintf(text, sizeof(text), "%lldm%02llds", s / 60, s % 60);
  } else {
    std::snprintf(text, sizeof(text), "%llds", s);
  }
  return text;
}

// Seconds left from the rate over the last `window`, not since the start: a
// training run's first steps make no updates and go a hundred times faster
// than the rest, and a rate averaged since the start promised a 3.5-hour MT50
// run in 52 minutes. Until the window has filled, the rate is the one since
// the first Update.
class RemainingTime {
 public:
  using Clock = std::chrono::steady_clock;

  explicit RemainingTime(std::chrono::duration<double> window = std::chrono::seconds(60))
      : window_(window) {}

  // `done` of `total` at `now`. Returns the seconds left, or -1 while no rate
  // is known (the first call, or nothing done since the oldest sample).
  double Update(double done, double total, Clock::time_point now = Clock::now()) {
    // A sample every 1/32 of the window keeps the memory small however often
    // this is called.
    if (samples_.empty() || now - samples_.back().first >= window_ / 32) {
      samples_.emplace_back(now, done);
    }
    while (samples_.size() > 1 && now - samples_[1].first >= window_) samples_.pop_front();
    const auto& [then, done_then] = samples_.front();
    const double elapsed = std::chrono::duration<double>(now - then).count();
    const double progress = done - done_then;
    if (elapsed <= 0 || progress <= 0) return -1;
    return std::max(0.0, total - done) * elapsed / progress;
  }

  // A new phase whose rate has nothing to do with the last one's.
  void Reset() { samples_.clear(); }

 private:
  std::chrono::duration<double> window_;
  std::deque<std::pair<Clock::time_point, double>> samples_;
};

}  // namespace manyworlds::cli

#endif  // APPS_MANYWORLDS_REMAINING_TIME_H_
