#pragma once
// Zero-velocity update: while the camera sees the scene stand still, the body's velocity is zero
// to within sigma. Without it a still monocular rig has no visual information on translation (no
// parallax, no triangulated tracks) and only the IMU's drift moves it; the drift then gives the
// tracks a false baseline (OpenVINS applies the same update on its static stretches).
//
// Parameter block: speed_bias (9: v_W, b_g, b_a).   r = v_W / sigma
#include <ceres/sized_cost_function.h>

namespace navaid::estimation {

class ZeroVelocityFactor final : public ceres::SizedCostFunction<3, 9> {
 public:
  /// Throws Error unless sigma is finite and > 0 [m/s].
  explicit ZeroVelocityFactor(double sigma_mps);

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

 private:
  double inverse_sigma_;
};

}  // namespace navaid::estimation
