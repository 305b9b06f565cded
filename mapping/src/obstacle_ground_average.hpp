#pragma once
// The running average of the ground plane (thesis "Ground Plane Filtering"): it remembers how far
// the ground is from the sensor, so that a horizontal surface at another height (a table) is
// recognised as a false ground detection and the remembered plane is used instead.
// Private to the obstacle pipeline.
#include <cstddef>

#include "navaid/mapping/obstacle_scan.hpp"

namespace navaid::mapping {

class GroundAverage {
 public:
  /// `frames` >= 1: cumulative mean of the first `frames` planes, then weight 1 / frames.
  explicit GroundAverage(int frames) : frames_(frames) {}

  bool empty() const { return count_ == 0; }
  std::size_t count() const { return count_; }
  /// Normalized mean normal and mean offset D_avg (meaningful when !empty()).
  GroundPlane plane() const;
  /// |D - D_avg| (0 while empty: the first plane has nothing to disagree with).
  double offset_deviation(const GroundPlane& p) const;
  void add(const GroundPlane& p);
  void reset() { count_ = 0; }

 private:
  int frames_;
  std::size_t count_ = 0;
  Eigen::Vector3d normal_sum_ = Eigen::Vector3d::Zero();  // running mean of unit normals
  double offset_ = 0.0;
};

}  // namespace navaid::mapping
