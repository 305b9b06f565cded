#include "navaid/estimation/factors/zero_velocity_factor.hpp"

#include <cmath>
#include <string>

#include "navaid/core/errors.hpp"

namespace navaid::estimation {

ZeroVelocityFactor::ZeroVelocityFactor(double sigma_v_mps, const Vec3& mean_gyro, const Vec3& sigma_gyro)
    : mean_gyro_(mean_gyro) {
  if (!std::isfinite(sigma_v_mps) || !(sigma_v_mps > 0))
    throw Error("ZeroVelocityFactor: sigma_v must be finite and > 0 m/s, got " + std::to_string(sigma_v_mps));
  if (!sigma_gyro.allFinite() || !(sigma_gyro.minCoeff() > 0))
    throw Error("ZeroVelocityFactor: every sigma_gyro must be finite and > 0 rad/s");
  if (!mean_gyro.allFinite()) throw Error("ZeroVelocityFactor: the mean gyro must be finite");
  inverse_sigma_v_ = 1.0 / sigma_v_mps;
  inverse_sigma_gyro_ = sigma_gyro.cwiseInverse();
}

bool ZeroVelocityFactor::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  const double* speed_bias = parameters[0];
  for (int i = 0; i < 3; ++i) {
    residuals[i] = inverse_sigma_v_ * speed_bias[i];
    residuals[3 + i] = inverse_sigma_gyro_[i] * (speed_bias[3 + i] - mean_gyro_[i]);
  }
  if (jacobians && jacobians[0]) {
    double* J = jacobians[0];  // 6 x 9, row major
    for (int k = 0; k < 54; ++k) J[k] = 0.0;
    for (int i = 0; i < 3; ++i) {
      J[i * 9 + i] = inverse_sigma_v_;
      J[(3 + i) * 9 + 3 + i] = inverse_sigma_gyro_[i];
    }
  }
  return true;
}

}  // namespace navaid::estimation
