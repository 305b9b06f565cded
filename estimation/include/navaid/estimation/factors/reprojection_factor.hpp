#pragma once
// Reprojection of a feature anchored at its first observation (VINS-Mono style, W-ROMA eq. 4 r_p).
//
// Parameter blocks: pose_anchor T_W_Ba (7), pose_target T_W_Bt (7), extrinsic T_B_C (7),
// inverse depth lambda (1) of the feature along the anchor camera's z axis.
// Measurements are undistorted normalized image coordinates m = (x/z, y/z) in each camera.
//   P_ct = T_B_C^-1 T_W_Bt^-1 T_W_Ba T_B_C (m_a / lambda),   m_a = [m_anchor, 1]
//   r    = (f / sigma_px) (P_ct.xy / P_ct.z - m_target)       (2-dim, predicted - measured)
// The residual lives on the normalized plane; the scale f / sigma_px (focal length in pixels,
// pixel noise sigma) makes it dimensionless, i.e. approximately the pixel error in sigmas.
// Callers wrap it in a Cauchy loss (ceres::CauchyLoss). Evaluate() returns false when the point
// is not in front of the target camera (z <= 1e-6 m), which Ceres treats as an invalid step.
// Anchor and target must be different parameter blocks (different keyframes).
#include <ceres/sized_cost_function.h>

#include <Eigen/Core>

namespace navaid::estimation {

class ReprojectionFactor final : public ceres::SizedCostFunction<2, 7, 7, 7, 1> {
 public:
  /// Throws ConfigError unless focal_px > 0 and sigma_px > 0.
  ReprojectionFactor(const Eigen::Vector2d& m_anchor, const Eigen::Vector2d& m_target, double focal_px,
                     double sigma_px);

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

  /// The same residual for other measurements (same weight), with its Jacobians w.r.t. the two
  /// measurements as well when d_m_anchor / d_m_target are not null (ReprojectionTdFactor moves
  /// the measurements with the time offset). Evaluate() is evaluate_at(the constructor's m).
  bool evaluate_at(double const* const* parameters, const Eigen::Vector2d& m_anchor, const Eigen::Vector2d& m_target,
                   double* residuals, double** jacobians, Eigen::Matrix2d* d_m_anchor,
                   Eigen::Matrix2d* d_m_target) const;

  double sqrt_information() const { return sqrt_information_; }  ///< f / sigma_px

 private:
  Eigen::Vector2d m_anchor_;
  Eigen::Vector2d m_target_;
  double sqrt_information_;
};

}  // namespace navaid::estimation
