#include "manyworlds/manipulation/push_from_behind.h"

#include <cmath>

namespace manyworlds::manipulation {

void PushFromBehind(const SawyerObs& o, const Vec3& object, const Vec3& target,
                    const PushParams& p, std::span<float> action) {
  double dx = target[0] - object[0], dy = target[1] - object[1];
  const double dist = std::hypot(dx, dy);
  if (dist > 1e-6) {
    dx /= dist;
    dy /= dist;
  }
  const double behind_x = object[0] - p.behind * dx, behind_y = object[1] - p.behind * dy;
  const double off = std::hypot(o.tcp[0] - behind_x, o.tcp[1] - behind_y);
  Vec3 to;
  if (off > 0.02) {
    // Rise before travelling (the object and fixtures are low), then come
    // down behind the object.
    to = o.tcp[2] < p.high - 0.02 && off > 0.03 ? Vec3{o.tcp[0], o.tcp[1], p.high}
                                                : Vec3{behind_x, behind_y, p.high};
    if (off < 0.03) to[2] = p.low;
  } else {
    to = {o.tcp[0] + 0.05 * dx, o.tcp[1] + 0.05 * dy, p.low};
  }
  MoveTo(o.hand, {to[0], to[1], to[2] + kTcpBelowHand}, 1.0, action);
}

}  // namespace manyworlds::manipulation
