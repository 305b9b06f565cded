#pragma once
// IMU preintegration factor between keyframes i and j (see imu_preintegration.hpp).
//
// Parameter blocks: pose_i (7), speed_bias_i (9), pose_j (7), speed_bias_j (9)
// (layouts in pose_parametrization.hpp). With dt = t_j - t_i, db = b_i - b_lin and the first-order
// bias-corrected preintegrated values alpha, beta, gamma, the 15-dim residual is
//   r_theta = Log(gamma(b_g,i)^-1 R_i^T R_j)
//   r_alpha = R_i^T (p_j - p_i - v_i dt - g_W dt^2 / 2) - alpha(b_i)
//   r_beta  = R_i^T (v_j - v_i - g_W dt) - beta(b_i)
//   r_bg    = b_g,j - b_g,i
//   r_ba    = b_a,j - b_a,i
// whitened as L^-1 r with P = L L^T the preintegrated covariance (r^T P^-1 r), so its units are
// standard deviations. Jacobians are analytic (right perturbations, lifted to the quaternion).
#include <ceres/sized_cost_function.h>

#include "navaid/estimation/imu_preintegration.hpp"

namespace navaid::estimation {

class ImuFactor final : public ceres::SizedCostFunction<15, 7, 9, 7, 9> {
 public:
  /// Keeps a copy of the preintegration (after repropagate(), build a new factor). Throws Error
  /// when it spans no time or its covariance is not positive definite (all densities zero).
  explicit ImuFactor(const ImuPreintegration& preintegration);

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

  const ImuPreintegration& preintegration() const { return preintegration_; }
  /// L^-1 with covariance P = L L^T.
  const Mat15& sqrt_information() const { return sqrt_information_; }

 private:
  ImuPreintegration preintegration_;
  Mat15 sqrt_information_;
};

}  // namespace navaid::estimation
