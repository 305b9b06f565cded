#include "navaid/estimation/factors/magnetometer_yaw_factor.hpp"

#include <cmath>

#include "navaid/core/errors.hpp"
#include "navaid/estimation/factors/pose_parametrization.hpp"

namespace navaid::estimation {

namespace {

constexpr double kMinHorizontalFraction = 1e-3;

bool has_horizontal(const Vec3& v) { return v.head<2>().norm() >= kMinHorizontalFraction * v.norm() && v.norm() > 0; }

double wrap_pi(double a) { return std::remainder(a, 2.0 * M_PI); }

}  // namespace

double magnetometer_yaw_sigma(double sigma_field, const Vec3& reference_field_enu) {
  if (!(sigma_field > 0.0) || !std::isfinite(sigma_field)) {
    throw ConfigError("magnetometer_yaw_sigma", "sigma_field", "must be finite and > 0");
  }
  if (!reference_field_enu.allFinite() || !has_horizontal(reference_field_enu)) {
    throw ConfigError("magnetometer_yaw_sigma", "reference_field_enu", "needs a horizontal component");
  }
  return sigma_field / reference_field_enu.head<2>().norm();
}

MagnetometerYawFactor::MagnetometerYawFactor(const Vec3& field_B, const Vec3& reference_field_enu, double sigma_yaw)
    : field_B_(field_B), sigma_yaw_(sigma_yaw) {
  if (!field_B.allFinite() || !(field_B.norm() > 0.0)) {
    throw Error("MagnetometerYawFactor: the measured field is zero or not finite");
  }
  if (!reference_field_enu.allFinite() || !has_horizontal(reference_field_enu)) {
    throw ConfigError("magnetometer_yaw_factor", "reference_field_enu", "needs a horizontal component");
  }
  if (!(sigma_yaw > 0.0) || !std::isfinite(sigma_yaw)) {
    throw ConfigError("magnetometer_yaw_factor", "sigma_yaw", "must be finite and > 0");
  }
  reference_heading_ = std::atan2(reference_field_enu.y(), reference_field_enu.x());
}

bool MagnetometerYawFactor::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  const SE3 T_W_B = pose_from_block(parameters[0]);
  const Mat3 Rz = enu_alignment_from_block(parameters[1]).rotation();
  const Mat3 R_W_B = T_W_B.rotation();
  const Vec3 h = Rz * R_W_B * field_B_;
  if (!has_horizontal(h)) return false;
  residuals[0] = wrap_pi(std::atan2(h.y(), h.x()) - reference_heading_) / sigma_yaw_;
  if (jacobians == nullptr) return true;

  // d atan2(h_y, h_x) / dh, scaled by 1 / sigma.
  const double n2 = h.x() * h.x() + h.y() * h.y();
  const Eigen::RowVector3d d_heading = Eigen::RowVector3d(-h.y(), h.x(), 0.0) / (n2 * sigma_yaw_);
  if (jacobians[0]) {
    Eigen::Matrix<double, 1, 6> J;
    J.leftCols<3>().setZero();
    J.rightCols<3>() = d_heading * (-Rz * R_W_B * hat(field_B_));
    write_pose_jacobian<1>(J, parameters[0], jacobians[0]);
  }
  if (jacobians[1]) {
    // Rotating h about z by d(yaw) turns its heading by exactly d(yaw).
    jacobians[1][0] = 1.0 / sigma_yaw_;
    jacobians[1][1] = jacobians[1][2] = jacobians[1][3] = 0.0;
  }
  return true;
}

}  // namespace navaid::estimation
