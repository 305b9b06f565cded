#pragma once
// Magnetometer heading factor. The calibrated field m_B (hard and soft iron removed) is rotated
// into ENU with the current attitude estimate, and only its horizontal direction is compared with
// the reference field's (declination included in m_ref_ENU):
//
//   h = Rz(yaw) R_W_B m_B                                   (field in ENU as the state predicts it)
//   r = wrap(atan2(h_N, h_E) - atan2(m_ref,N, m_ref,E)) / sigma_yaw      (1-dim, radians / sigma)
//
// Comparing headings rather than 3D vectors makes the factor blind to the field's magnitude and
// inclination, which local iron and indoor structures distort far more than its direction
// (a heading error of the full vector residual would otherwise leak into roll and pitch).
// Parameter blocks: pose T_W_B (7), alignment [yaw, t_x, t_y, t_z] (4; only yaw enters).
// Evaluate() returns false when h has no horizontal component (|h_EN| < 1e-3 |h|).
#include <ceres/sized_cost_function.h>

#include "navaid/core/geometry.hpp"

namespace navaid::estimation {

/// Heading sigma [rad] of a field measurement with per-axis noise sigma_field: sigma / |m_horizontal|.
/// Throws ConfigError unless sigma_field > 0 and the reference field has a horizontal component.
double magnetometer_yaw_sigma(double sigma_field, const Vec3& reference_field_enu);

class MagnetometerYawFactor final : public ceres::SizedCostFunction<1, 7, 4> {
 public:
  /// Throws ConfigError unless sigma_yaw > 0 and the reference field has a horizontal component,
  /// Error when the measured field is zero or not finite.
  MagnetometerYawFactor(const Vec3& field_B, const Vec3& reference_field_enu, double sigma_yaw);

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

 private:
  Vec3 field_B_;
  double reference_heading_;
  double sigma_yaw_;
};

}  // namespace navaid::estimation
