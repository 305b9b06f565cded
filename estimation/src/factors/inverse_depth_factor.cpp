#include "navaid/estimation/factors/inverse_depth_factor.hpp"

#include <cmath>
#include <string>

#include "navaid/core/errors.hpp"

namespace navaid::estimation {

double inverse_depth_sigma(double disparity_sigma_px, double focal_px, double baseline_m) {
  auto require = [](double v, const char* key) {
    if (!(v > 0.0) || !std::isfinite(v)) throw ConfigError("inverse_depth_sigma", key, "must be finite and > 0");
  };
  require(disparity_sigma_px, "depth_disparity_sigma_px");
  require(focal_px, "focal_px");
  require(baseline_m, "depth_baseline_m");
  return disparity_sigma_px / (focal_px * baseline_m);
}

InverseDepthFactor::InverseDepthFactor(double measured_depth_m, double sigma_lambda)
    : measured_inverse_depth_(1.0 / measured_depth_m), sigma_lambda_(sigma_lambda) {
  if (!(measured_depth_m > 0.0) || !std::isfinite(measured_depth_m)) {
    throw Error("InverseDepthFactor: measured depth must be finite and > 0, got " + std::to_string(measured_depth_m));
  }
  if (!(sigma_lambda > 0.0) || !std::isfinite(sigma_lambda)) {
    throw ConfigError("inverse_depth_factor", "sigma_lambda", "must be finite and > 0");
  }
}

bool InverseDepthFactor::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  residuals[0] = (measured_inverse_depth_ - parameters[0][0]) / sigma_lambda_;
  if (jacobians != nullptr && jacobians[0] != nullptr) jacobians[0][0] = -1.0 / sigma_lambda_;
  return true;
}

}  // namespace navaid::estimation
