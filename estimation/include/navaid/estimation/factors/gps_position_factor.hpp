#pragma once
// GNSS position fix in the local ENU frame, tied to the world frame W through the 4-DOF alignment
// T_ENU_W (yaw about z, then a translation; W and ENU are both gravity-aligned, z up).
//
// Parameter blocks: pose T_W_B (7) at the fix time, alignment [yaw, t_x, t_y, t_z] (4).
//   p_ENU^ = Rz(yaw) (p_W_B + R_W_B l_B) + t      (l_B: antenna lever arm in the body frame)
//   r      = L^-1 (p_ENU^ - z_ENU),   Sigma = L L^T the fix covariance (GpsFix::covariance_enu)
// Units: metres; the residual is in standard deviations.
//
// GpsPositionBiasFactor adds a third block, the fix's slowly varying multipath bias b (3, ENU),
// estimated as a Gauss-Markov process (gauss_markov_factor.hpp):
//   r = L^-1 (p_ENU^ + b - z_ENU),   Sigma = the white part of the fix covariance
#include <ceres/sized_cost_function.h>

#include "navaid/core/geometry.hpp"

namespace navaid::estimation {

class GpsPositionFactor final : public ceres::SizedCostFunction<3, 7, 4> {
 public:
  /// Throws Error when the covariance is not symmetric positive definite or a value is not finite.
  GpsPositionFactor(const Vec3& position_enu, const Mat3& covariance_enu, const Vec3& lever_arm_B);

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

  const Mat3& sqrt_information() const { return sqrt_information_; }  ///< L^-1

 private:
  Vec3 position_enu_;
  Vec3 lever_arm_B_;
  Mat3 sqrt_information_;
};

class GpsPositionBiasFactor final : public ceres::SizedCostFunction<3, 7, 4, 3> {
 public:
  /// Same checks as GpsPositionFactor; `covariance_enu` is the white (uncorrelated) part.
  GpsPositionBiasFactor(const Vec3& position_enu, const Mat3& covariance_enu, const Vec3& lever_arm_B);

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

 private:
  GpsPositionFactor position_;
};

}  // namespace navaid::estimation
