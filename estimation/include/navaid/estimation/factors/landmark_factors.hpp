#pragma once
// Visual factors on a 3-DOF anchored landmark l = [x_a, y_a, lambda]: the bearing of the feature
// on the anchor camera's normalized plane and its inverse depth there
// (estimator.features.anchor_bearing = estimated).
//
// ReprojectionFactor and Depth3dFactor take the anchor's bearing as the measured m_anchor, i.e.
// free of noise. It is not: the anchor pixel has the same noise as every other observation, and
// that error is common to all of the track's residuals, so treating it as exact over-counts the
// information on the pose of the anchor relative to the targets by up to the number of targets.
// Here the bearing is estimated and the anchor observation is a factor like the others:
//
//   AnchorBearingFactor      r = (f / sigma_px) ([x_a, y_a] - m_anchor)          (2, block l)
//   AnchorInverseDepthFactor r = (lambda - 1 / Z_anchor) / sigma_lambda          (1, block l)
//   LandmarkReprojectionFactor, LandmarkDepth3dFactor: ReprojectionFactor / Depth3dFactor with
//     m_anchor = [x_a, y_a] and lambda from l (blocks: anchor pose 7, target pose 7, T_B_C 7, l 3)
//
// (OpenVINS' anchored inverse-depth features are 3-DOF in the same way.) Pixel and disparity
// noise are independent, so the two anchor factors are independent too.
//
// Time-offset versions (one more block, td [s]; time_offset_factors.hpp explains the motion
// model): the anchor's measurement moves in AnchorBearingTdFactor (the bearing is the feature's
// direction at the anchor state's time), the target's measurement and depth in the target factors.
#include <ceres/sized_cost_function.h>

#include <Eigen/Core>

#include "navaid/estimation/factors/depth_3d_factor.hpp"
#include "navaid/estimation/factors/reprojection_factor.hpp"
#include "navaid/estimation/factors/time_offset_factors.hpp"

namespace navaid::estimation {

inline constexpr int kLandmarkSize = 3;  ///< [x_a, y_a, lambda]

class AnchorBearingFactor final : public ceres::SizedCostFunction<2, kLandmarkSize> {
 public:
  /// Throws Error unless m_anchor is finite and ConfigError unless focal_px, sigma_px > 0.
  AnchorBearingFactor(const Eigen::Vector2d& m_anchor, double focal_px, double sigma_px);
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

 private:
  Eigen::Vector2d m_anchor_;
  double sqrt_information_;
};

class AnchorInverseDepthFactor final : public ceres::SizedCostFunction<1, kLandmarkSize> {
 public:
  /// Throws Error unless depth_m > 0 and ConfigError unless sigma_lambda > 0.
  AnchorInverseDepthFactor(double depth_m, double sigma_lambda);
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

 private:
  double measured_inverse_depth_;
  double sigma_lambda_;
};

class LandmarkReprojectionFactor final : public ceres::SizedCostFunction<2, 7, 7, 7, kLandmarkSize> {
 public:
  /// As ReprojectionFactor (m_target measured in the target camera).
  LandmarkReprojectionFactor(const Eigen::Vector2d& m_target, double focal_px, double sigma_px);
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

 private:
  Eigen::Vector2d m_target_;
  ReprojectionFactor plain_;
};

class LandmarkDepth3dFactor final : public ceres::SizedCostFunction<3, 7, 7, 7, kLandmarkSize> {
 public:
  /// As Depth3dFactor; the point covariance uses the measured target bearing and depth.
  LandmarkDepth3dFactor(const Eigen::Vector2d& m_target, double depth_j_m, double focal_px, double sigma_lambda,
                        double sigma_px, Depth3dCovariance model = Depth3dCovariance::kFull);
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

 private:
  Eigen::Vector2d m_target_;
  double depth_m_;
  Depth3dFactor plain_;
};

class AnchorBearingTdFactor final : public ceres::SizedCostFunction<2, kLandmarkSize, 1> {
 public:
  /// Throws Error unless the observation is finite; ConfigError as AnchorBearingFactor.
  AnchorBearingTdFactor(const TimedObservation& anchor, double focal_px, double sigma_px);
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

 private:
  TimedObservation anchor_;
  double sqrt_information_;
};

class LandmarkReprojectionTdFactor final : public ceres::SizedCostFunction<2, 7, 7, 7, kLandmarkSize, 1> {
 public:
  LandmarkReprojectionTdFactor(const TimedObservation& target, double focal_px, double sigma_px);
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

 private:
  TimedObservation target_;
  ReprojectionFactor plain_;
};

class LandmarkDepth3dTdFactor final : public ceres::SizedCostFunction<3, 7, 7, 7, kLandmarkSize, 1> {
 public:
  /// depth_rate_mps as Depth3dTdFactor.
  LandmarkDepth3dTdFactor(const TimedObservation& target, double depth_j_m, double depth_rate_mps, double focal_px,
                          double sigma_lambda, double sigma_px, Depth3dCovariance model = Depth3dCovariance::kFull);
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

 private:
  TimedObservation target_;
  double depth_m_, depth_rate_mps_;
  Depth3dFactor plain_;
};

}  // namespace navaid::estimation
