#pragma once
// Gaussian prior on one state (pose 7, speed-bias 9): the sliding window's initial state and,
// when marginalization is off, the pin that holds the gauge at the oldest keyframe. Residual in
// StateEstimate's covariance order, whitened: r = L^-1 [Log(R0^T R), p - p0, v - v0, b_g - b_g0, b_a - b_a0],
// covariance = L L^T. d r_theta / d dtheta (right perturbation) = Jr^-1(r_theta).
#include <ceres/sized_cost_function.h>

#include "navaid/core/state_estimate.hpp"

namespace navaid::estimation {

class StatePriorFactor final : public ceres::SizedCostFunction<15, 7, 9> {
 public:
  /// Throws Error unless the covariance is symmetric positive definite.
  StatePriorFactor(const SE3& T_W_B, const Vec3& v_W, const Vec3& b_g, const Vec3& b_a, const Mat15& covariance);

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

 private:
  SE3 T_W_B_;
  Eigen::Matrix<double, 9, 1> speed_bias_;
  Mat15 sqrt_information_;
};

}  // namespace navaid::estimation
