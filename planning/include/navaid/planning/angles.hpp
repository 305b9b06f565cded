#pragma once
// Angles of the planning layer: headings are yaw about W's z axis, relative headings are
// counter-clockwise positive (to the user's left), everything wrapped into (-pi, pi].
#include <cmath>

namespace navaid::planning {

inline constexpr double kPi = 3.14159265358979323846;

/// a wrapped into (-pi, pi] [rad].
inline double wrap_angle(double a) {
  const double w = std::remainder(a, 2.0 * kPi);
  return w <= -kPi ? w + 2.0 * kPi : w;
}

inline double deg_to_rad(double deg) { return deg * kPi / 180.0; }
inline double rad_to_deg(double rad) { return rad * 180.0 / kPi; }

}  // namespace navaid::planning
