#pragma once
// Depth measurement of a feature in its anchor keyframe (W-ROMA §V-B, r_d^k):
//   e = 1 / Z - lambda,   r = e / sigma_lambda,   sigma_lambda = sigma_d / (f b)
// Z is the RGB-D depth [m] measured at the feature in the anchor camera, the frame in which the
// inverse depth lambda is defined (for depths measured in other keyframes, see
// Depth3dFactor). For a structured-light / stereo camera the disparity is d = f b / Z, so a
// disparity noise sigma_d [px] gives 1/Z = d / (f b) a noise sigma_d / (f b) exactly
// (f: focal length [px], b: baseline [m]). Parameter block: lambda (1) [1/m].
#include <ceres/sized_cost_function.h>

namespace navaid::estimation {

/// sigma_lambda = sigma_d / (f b) [1/m]. Throws ConfigError unless all three are > 0.
double inverse_depth_sigma(double disparity_sigma_px, double focal_px, double baseline_m);

class InverseDepthFactor final : public ceres::SizedCostFunction<1, 1> {
 public:
  /// Throws Error unless measured_depth_m > 0 and ConfigError unless sigma_lambda > 0.
  InverseDepthFactor(double measured_depth_m, double sigma_lambda);

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

 private:
  double measured_inverse_depth_;
  double sigma_lambda_;
};

}  // namespace navaid::estimation
