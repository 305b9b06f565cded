#pragma once
// A tracking estimate at a planar pose with chosen position and attitude sigmas, for the guidance
// tests (eLabrador chain, Smart Cane loop).
#include "navaid/core/state_estimate.hpp"
#include "navaid/mapping/cost_map.hpp"

namespace navaid::planning {

inline StateEstimate planar_estimate(mapping::Vec2 p, double yaw, double sigma_xy, double sigma_yaw, Timestamp t = 0) {
  StateEstimate e;
  e.t = t;
  e.mode = EstimatorMode::kRgbdVio;
  e.T_W_B = SE3(Quat(Eigen::AngleAxisd(yaw, Vec3::UnitZ())), Vec3(p.x(), p.y(), 1.5));
  e.covariance = Mat15::Identity() * 1e-6;
  e.covariance.block<3, 3>(0, 0) = Mat3::Identity() * sigma_yaw * sigma_yaw;
  e.covariance.block<3, 3>(3, 3) = Mat3::Identity() * sigma_xy * sigma_xy;
  return e;
}

}  // namespace navaid::planning
