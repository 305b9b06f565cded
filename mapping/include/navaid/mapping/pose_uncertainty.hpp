#pragma once
// How sure the estimator is of a pose, in the numbers the map acts on, and the gate that keeps
// uncertain or unlocalised frames out of the map.
//
// From StateEstimate::covariance (state_estimate.hpp: rotation error on the right, position error
// in W):
//   sigma_xy  = sqrt(largest eigenvalue of the x-y block of the position covariance) [m]: the
//               horizontal standard deviation in the worst direction;
//   sigma_z   = sqrt(position covariance zz) [m];
//   sigma_yaw = sqrt(e_z^T R Sigma_theta R^T e_z) [rad]: the right-multiplied rotation error moved
//               into W (dtheta_W = R dtheta_B), its component about gravity.
#include <cstddef>
#include <string>
#include <vector>

#include "navaid/core/config.hpp"
#include "navaid/core/state_estimate.hpp"

namespace navaid::mapping {

struct PoseUncertainty {
  double sigma_xy = 0.0;
  double sigma_z = 0.0;
  double sigma_yaw = 0.0;
};

/// Throws navaid::Error when the pose and position/rotation blocks of the covariance are not
/// finite, not symmetric or not positive definite (the message gives the estimate's time).
PoseUncertainty pose_uncertainty(const StateEstimate& estimate);

/// Which uncertainty the gate and the inflation act on.
enum class UncertaintyScope {
  /// The estimate's own sigma: its uncertainty relative to where the estimator started. A
  /// visual-inertial estimator's grows with the distance walked (measured on route2: 0.4 m per
  /// 100 m) while the map around the user stays consistent.
  kAbsolute,
  /// What the estimate has become less sure of over the last window_s seconds, the time in which
  /// the voxels around the user were mapped: sigma_rel^2 = sigma^2(t) - sigma^2(t - window_s),
  /// floored at 0 (errors that accumulate as a random walk have independent increments). A jump
  /// in uncertainty (a restart, a long dark stretch) still trips the gate.
  kWindow,
};

struct MappingGateConfig {
  double max_sigma_xy_m = 0.5;    ///< a frame less sure than this horizontally is not mapped
  double max_sigma_yaw_rad = 0.0872664626;  ///< 5 deg: at 5 m range a 5 deg yaw error moves points 0.44 m
  UncertaintyScope scope = UncertaintyScope::kWindow;
  double window_s = 10.0;         ///< kWindow: about the time a 10 m window takes to walk through
};

/// Keys mapping.gate.max_sigma_xy_m, mapping.gate.max_sigma_yaw_deg (degrees in the file),
/// mapping.gate.scope (window | absolute) and mapping.gate.window_s.
MappingGateConfig read_mapping_gate_config(const Config& config);

/// The recent history of an estimate's uncertainty, for UncertaintyScope::kWindow.
class UncertaintyWindow {
 public:
  /// Adds the uncertainty at time t (non-decreasing times) and returns the uncertainty gained
  /// over the last window_s seconds (the whole history while it is shorter than the window:
  /// relative to the oldest sample).
  PoseUncertainty add(Timestamp t, const PoseUncertainty& u, double window_s);

 private:
  struct Sample {
    Timestamp t;
    PoseUncertainty u;
  };
  std::vector<Sample> samples_;  ///< oldest first; trimmed to the window
};

enum class GateDecision { kMap, kSkipMode, kSkipUncertain };

/// kSkipMode for estimates initializing or lost (never mapped), kSkipUncertain when sigma_xy or
/// sigma_yaw exceed the limits, else kMap.
GateDecision gate(const StateEstimate& estimate, const PoseUncertainty& u, const MappingGateConfig& config);

}  // namespace navaid::mapping
