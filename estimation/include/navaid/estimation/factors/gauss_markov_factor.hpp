#pragma once
// First-order Gauss-Markov process between two samples of a slowly varying error, e.g. a GNSS
// multipath bias: b_k = phi b_{k-1} + w, phi = exp(-dt / tau), w ~ N(0, (1 - phi^2) Sigma), where
// Sigma is the process's stationary covariance.
//
// Parameter blocks: b_{k-1} (N), b_k (N).   r = S (b_k - phi b_{k-1}),  S^T S = ((1 - phi^2) Sigma)^-1
#include <ceres/sized_cost_function.h>

#include "navaid/core/geometry.hpp"

namespace navaid::estimation {

class GaussMarkovFactor final : public ceres::SizedCostFunction<3, 3, 3> {
 public:
  /// Throws Error unless dt >= 0, tau > 0, dt / tau is not so small that the step has no noise
  /// (phi < 1 - 1e-12) and Sigma is symmetric positive definite.
  GaussMarkovFactor(double dt_s, double tau_s, const Mat3& stationary_covariance);

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

  double phi() const { return phi_; }

 private:
  double phi_;
  Mat3 sqrt_information_;
};

/// Square-root information L^-1 of a covariance Sigma = L L^T; throws Error (naming `what`) when
/// Sigma is not symmetric positive definite or not finite.
Mat3 sqrt_information_of(const Mat3& covariance, const char* what);

}  // namespace navaid::estimation
