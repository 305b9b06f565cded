#include "navaid/mapping/obstacle_scan.hpp"

#include <algorithm>
#include <cmath>

namespace navaid::mapping {

ObstacleScan ObstacleScan::empty(std::size_t bins, double min_bearing_rad, double bearing_increment_rad) {
  constexpr float kInf = std::numeric_limits<float>::infinity();
  const Eigen::Vector3f nan = Eigen::Vector3f::Constant(std::numeric_limits<float>::quiet_NaN());
  ObstacleScan s;
  s.min_bearing_rad = min_bearing_rad;
  s.bearing_increment_rad = bearing_increment_rad;
  s.ranges.assign(bins, kInf);
  s.nearest_U.assign(bins, nan);
  s.drop_off_ranges.assign(bins, kInf);
  s.drop_off_nearest_U.assign(bins, nan);
  return s;
}

std::optional<std::size_t> ObstacleScan::bin_of(double bearing_rad) const {
  if (ranges.empty() || !(bearing_increment_rad > 0.0) || !std::isfinite(bearing_rad)) return std::nullopt;
  const double k = std::round((bearing_rad - min_bearing_rad) / bearing_increment_rad);
  if (k < 0.0 || k > static_cast<double>(ranges.size() - 1)) return std::nullopt;
  return static_cast<std::size_t>(k);
}

float ObstacleScan::min_range() const {
  float m = std::numeric_limits<float>::infinity();
  for (float r : ranges) m = std::min(m, r);
  return m;
}

}  // namespace navaid::mapping
