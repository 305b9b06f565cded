#include "obstacle_ground_average.hpp"

#include <algorithm>
#include <cmath>

namespace navaid::mapping {

GroundPlane GroundAverage::plane() const {
  GroundPlane p;
  p.normal_C = normal_sum_.normalized();
  p.offset_m = offset_;
  return p;
}

double GroundAverage::offset_deviation(const GroundPlane& p) const {
  return empty() ? 0.0 : std::abs(p.offset_m - offset_);
}

void GroundAverage::add(const GroundPlane& p) {
  ++count_;
  // 1/n while n <= frames (the plain mean), then a fixed 1/frames: old frames fade out.
  const double w = 1.0 / static_cast<double>(std::min<std::size_t>(count_, static_cast<std::size_t>(frames_)));
  normal_sum_ += w * (p.normal_C - normal_sum_);
  offset_ += w * (p.offset_m - offset_);
}

}  // namespace navaid::mapping
