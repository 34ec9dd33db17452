#include "manyworlds/manipulation/reward_utils.h"

#include <algorithm>
#include <cmath>

namespace manyworlds::manipulation {

double Distance(const Vec3& a, const Vec3& b) {
  const double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

double LongTailTolerance(double x, double low, double high, double margin) {
  if (x >= low && x <= high) return 1.0;
  if (margin <= 0) return 0.0;
  const double d = (x < low ? low - x : x - high) / margin;
  // s^2 = 1 / value_at_margin - 1 = 9 makes the value 0.1 at d = 1.
  return 1.0 / (9.0 * d * d + 1.0);
}

double RectPrismTolerance(const Vec3& x, const Vec3& zero, const Vec3& one) {
  double product = 1.0;
  for (int i = 0; i < 3; ++i) {
    const double lo = std::min(zero[i], one[i]), hi = std::max(zero[i], one[i]);
    if (!(x[i] >= lo && x[i] <= hi)) return 1.0;
    product *= (x[i] - zero[i]) / (one[i] - zero[i]);
  }
  return product;
}

double GaussianTolerance(double x, double low, double high, double margin) {
  if (x >= low && x <= high) return 1.0;
  if (margin <= 0) return 0.0;
  const double d = (x < low ? low - x : x - high) / margin;
  // exp(-s^2 / 2) = 0.1 at d = 1.
  const double scale = std::sqrt(-2.0 * std::log(0.1));
  return std::exp(-0.5 * (d * scale) * (d * scale));
}

double HamacherProduct(double a, double b) {
  a = std::clamp(a, 0.0, 1.0);
  b = std::clamp(b, 0.0, 1.0);
  const double denominator = a + b - a * b;
  return denominator > 0 ? a * b / denominator : 0.0;
}

double GripperCagingReward(const CagingInputs& in, const CagingParams& p) {
  // y caging, per pad: the margin is how far the pad starts from the
  // success band around the object's initial position.
  double caging_pad[2];
  const Vec3* pads[2] = {&in.left_pad, &in.right_pad};
  for (int i = 0; i < 2; ++i) {
    const double to_obj = std::abs((*pads[i])[1] - in.obj[1]);
    const double to_obj_init = std::abs((*pads[i])[1] - in.obj_init[1]);
    const double margin = std::abs(to_obj_init - p.pad_success_thresh);
    caging_pad[i] = LongTailTolerance(to_obj, p.obj_radius, p.pad_success_thresh, margin);
  }
  const double caging_y = HamacherProduct(caging_pad[0], caging_pad[1]);

  // xz alignment of the tcp with the object.
  const double dx = in.tcp[0] - in.obj[0], dz = in.tcp[2] - in.obj[2];
  const double tcp_xz = std::sqrt(dx * dx + dz * dz);
  const double ix = in.obj_init[0] - in.tcp_init[0], iz = in.obj_init[2] - in.tcp_init[2];
  const double xz_margin = std::sqrt(ix * ix + iz * iz) - p.xz_thresh;
  const double caging_xz = LongTailTolerance(tcp_xz, 0.0, p.xz_thresh, xz_margin);

  const double effort = p.desired_gripper_effort;
  const double gripper_closed = std::min(std::max(0.0, in.gripper_action), effort) / effort;
  const double caging = HamacherProduct(caging_y, caging_xz);
  const double gripping = caging > 0.97 ? gripper_closed : 0.0;
  double result = HamacherProduct(caging, gripping);
  if (p.high_density) result = (result + caging) / 2.0;
  if (p.medium_density) {
    const double reach_margin =
        std::abs(Distance(in.obj_init, in.tcp_init) - p.object_reach_radius);
    const double reach =
        LongTailTolerance(Distance(in.obj, in.tcp), 0.0, p.object_reach_radius, reach_margin);
    result = (result + reach) / 2.0;
  }
  return result;
}

}  // namespace manyworlds::manipulation
