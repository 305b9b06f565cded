#include "navaid/estimation/factors/zero_velocity_factor.hpp"

#include <cmath>
#include <string>

#include "navaid/core/errors.hpp"

namespace navaid::estimation {

ZeroVelocityFactor::ZeroVelocityFactor(double sigma_mps) {
  if (!std::isfinite(sigma_mps) || !(sigma_mps > 0))
    throw Error("ZeroVelocityFactor: sigma must be finite and > 0 m/s, got " + std::to_string(sigma_mps));
  inverse_sigma_ = 1.0 / sigma_mps;
}

bool ZeroVelocityFactor::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  const double* speed_bias = parameters[0];
  for (int i = 0; i < 3; ++i) residuals[i] = inverse_sigma_ * speed_bias[i];
  if (jacobians && jacobians[0]) {
    double* J = jacobians[0];  // 3 x 9, row major
    for (int k = 0; k < 27; ++k) J[k] = 0.0;
    for (int i = 0; i < 3; ++i) J[i * 9 + i] = inverse_sigma_;
  }
  return true;
}

}  // namespace navaid::estimation
