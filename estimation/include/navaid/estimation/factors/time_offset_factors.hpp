#pragma once
// Visual factors that also estimate the camera-IMU time offset td (VINS-Mono's online temporal
// calibration): ReprojectionFactor and Depth3dFactor with one more parameter block, td [s].
//
// A frame stamped t_cam (camera clock) was exposed at IMU time t_cam + td (t_imu = t_cam + td, as
// CameraCalibration::time_offset_s). The estimator put the frame's state at t_cam + td0, td0 the
// offset it corrected that frame with. Between the state's time and the exposure the feature moves
// with its image velocity v = dm/dt, so to first order it was, at the state's time, at
//
//   m(td) = m - (td - td0) v                (m, v on the normalized plane; v in 1/s)
//
// (exposure later than the state, td > td0: the feature has already moved on by (td - td0) v).
// The factors are the plain factors evaluated at m_anchor(td), m_target(td), each observation
// with its own v and td0, so the residuals and weights are the plain ones, and
//   d r / d td = -(d r / d m_anchor) v_anchor - (d r / d m_target) v_target.
// At td = td0 of both observations the residual is the plain factor's, bit for bit.
// Parameter blocks: pose_anchor (7), pose_target (7), extrinsic T_B_C (7), inverse depth (1), td (1).
// Depth3dTdFactor also moves the measured depth with its rate (dZ/dt, 0 when unknown):
//   Z(td) = Z - (td - td0_target) dZ/dt
// (walking at 1.2 m/s changes Z by 8 mm in 7 ms, more than a D455's depth noise at 1.5 m).
// Its weights stay those of the measured Z.
#include <ceres/sized_cost_function.h>

#include <Eigen/Core>

#include "navaid/estimation/factors/depth_3d_factor.hpp"
#include "navaid/estimation/factors/reprojection_factor.hpp"

namespace navaid::estimation {

/// One observation of a feature with what the time offset needs to move it.
struct TimedObservation {
  Eigen::Vector2d m = Eigen::Vector2d::Zero();         ///< undistorted normalized coordinates, as measured
  Eigen::Vector2d velocity = Eigen::Vector2d::Zero();  ///< v = dm/dt on the normalized plane [1/s]
  double td0_s = 0;  ///< the time offset the frame's time was corrected with [s]

  /// The observation moved to the state's time for a time offset td: m - (td - td0) v.
  Eigen::Vector2d at(double td_s) const { return m - (td_s - td0_s) * velocity; }
};

class ReprojectionTdFactor final : public ceres::SizedCostFunction<2, 7, 7, 7, 1, 1> {
 public:
  /// Throws Error unless m, velocity and td0 are finite; ConfigError as ReprojectionFactor.
  ReprojectionTdFactor(const TimedObservation& anchor, const TimedObservation& target, double focal_px,
                       double sigma_px);

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

 private:
  ReprojectionFactor plain_;
  TimedObservation anchor_, target_;
};

class Depth3dTdFactor final : public ceres::SizedCostFunction<3, 7, 7, 7, 1, 1> {
 public:
  /// depth_rate_mps: dZ/dt of the target's measured depth [m/s]. Evaluate() returns false when
  /// the moved depth is not positive. Throws Error unless m, velocity, td0 and the rate are finite;
  /// Error / ConfigError as Depth3dFactor.
  Depth3dTdFactor(const TimedObservation& anchor, const TimedObservation& target, double depth_j_m,
                  double depth_rate_mps, double focal_px, double sigma_lambda, double sigma_px = 1.5,
                  Depth3dCovariance model = Depth3dCovariance::kFull);

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

 private:
  Depth3dFactor plain_;
  TimedObservation anchor_, target_;
  double depth_m_, depth_rate_mps_;
};

}  // namespace navaid::estimation
