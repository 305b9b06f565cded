#pragma once
// Zero-velocity update: while the camera sees the scene stand still, the body neither moves nor
// turns. Its velocity is zero to within sigma_v, and the gyro's mean over the still stretch is its
// bias (zero angular rate) to within that mean's error. Without it a still monocular rig has no
// visual information (no parallax, no triangulated tracks): the IMU's drift would move it, turn it
// with the bias error, and give the tracks a false baseline (OpenVINS applies the same update,
// velocity and IMU readings, on its static stretches).
//
// Parameter block: speed_bias (9: v_W, b_g, b_a).
//   r = [v_W / sigma_v,  (b_g - mean_gyro) ./ sigma_gyro]
#include <ceres/sized_cost_function.h>

#include "navaid/core/geometry.hpp"

namespace navaid::estimation {

class ZeroVelocityFactor final : public ceres::SizedCostFunction<6, 9> {
 public:
  /// Throws Error unless sigma_v and every sigma_gyro are finite and > 0 and mean_gyro is finite.
  ZeroVelocityFactor(double sigma_v_mps, const Vec3& mean_gyro, const Vec3& sigma_gyro);

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

 private:
  double inverse_sigma_v_;
  Vec3 mean_gyro_;
  Vec3 inverse_sigma_gyro_;
};

}  // namespace navaid::estimation
