#pragma once
// Smooth synthetic trajectories for the metric tests: a walk that turns, climbs and rotates about
// every axis, so that no alignment is degenerate.
#include <cmath>
#include <vector>

#include "navaid/core/geometry.hpp"
#include "navaid/io/tum_trajectory.hpp"

namespace navaid::testing {

inline std::vector<io::StampedPose> synthetic_trajectory(std::size_t n, Duration period = 100'000'000,
                                                         Timestamp t0 = 1'000'000'000'000) {
  std::vector<io::StampedPose> poses;
  for (std::size_t i = 0; i < n; ++i) {
    const double s = 0.1 * static_cast<double>(i);
    io::StampedPose p;
    p.t = t0 + static_cast<Timestamp>(i) * period;
    p.T_W_B = SE3(quat_from_rpy(0.1 * std::sin(s), 0.2 * std::cos(0.5 * s), 0.4 * s),
                  Vec3(3.0 * std::cos(0.3 * s) + 0.5 * s, 2.0 * std::sin(0.5 * s), 1.0 + 0.3 * std::sin(0.7 * s)));
    poses.push_back(p);
  }
  return poses;
}

/// Every pose mapped by T_A_W: the same motion expressed in another world frame A.
inline std::vector<io::StampedPose> in_frame(const std::vector<io::StampedPose>& poses, const SE3& T_A_W) {
  std::vector<io::StampedPose> out = poses;
  for (auto& p : out) p.T_W_B = T_A_W * p.T_W_B;
  return out;
}

}  // namespace navaid::testing
