#include "manyworlds/manipulation/bar_push.h"

#include <cmath>

namespace manyworlds::manipulation::rotary {
namespace {

constexpr double kLow = 0.02;          // within this of the push depth: in
constexpr double kAligned = 0.012;     // xy error before coming down
constexpr double kAhead = 0.05;        // the push aims this far past the bar
constexpr double kClosed = 1.0;

}  // namespace

void PushBarAround(const SawyerObs& o, const BarPush& p, std::span<float> action) {
  const int ia = (p.depth + 1) % 3, ib = (p.depth + 2) % 3;
  // u: along the bar, out from the axis; t: the way the bar is to turn.
  const double ua = std::cos(p.bar_angle), ub = std::sin(p.bar_angle);
  const double ta = -p.direction * ub, tb = p.direction * ua;
  const auto at = [&](double along, double across, double depth) {
    Vec3 v{};
    v[ia] = p.center[ia] + along * ua + across * ta;
    v[ib] = p.center[ib] + along * ub + across * tb;
    v[p.depth] = depth;
    return v;
  };
  const auto hand_for_tcp = [](const Vec3& tcp) {
    return Vec3{tcp[0], tcp[1], tcp[2] + kTcpBelowHand};
  };
  const double ra = o.tcp[ia] - p.center[ia], rb = o.tcp[ib] - p.center[ib];
  const double along = ra * ua + rb * ub, across = ra * ta + rb * tb;
  // In: past the clearance toward the push depth.
  const double off = (o.tcp[p.depth] - p.height) * (p.clear > 0 ? 1.0 : -1.0);
  const bool in = off < kLow;
  const bool behind_bar = along > p.push_at - 0.025 && along < p.push_at + 0.03 &&
                          across < -0.005 && across > -p.standoff - 0.025;
  if (in && behind_bar) {
    MoveTo(o.hand, hand_for_tcp(at(p.push_at, kAhead, p.height)), kClosed, action);
    return;
  }
  const Vec3 ready = at(p.push_at, -p.standoff, p.height);
  const double error = std::hypot(o.tcp[ia] - ready[ia], o.tcp[ib] - ready[ib]);
  if (error > kAligned) {
    // Line up clear of the fixture (from in beside the bar: back out first).
    Vec3 clear = ready;
    clear[p.depth] = p.height + p.clear;
    if (in && error > 0.03) {
      clear = o.tcp;
      clear[p.depth] = p.height + p.clear;
    }
    MoveTo(o.hand, hand_for_tcp(clear), kClosed, action);
    return;
  }
  MoveTo(o.hand, hand_for_tcp(ready), kClosed, action);
}

}  // namespace manyworlds::manipulation::rotary
