#include "navaid/estimation/factors/gps_position_factor.hpp"

#include "navaid/core/errors.hpp"
#include "navaid/estimation/factors/gauss_markov_factor.hpp"
#include "navaid/estimation/factors/pose_parametrization.hpp"

namespace navaid::estimation {

GpsPositionFactor::GpsPositionFactor(const Vec3& position_enu, const Mat3& covariance_enu, const Vec3& lever_arm_B)
    : position_enu_(position_enu), lever_arm_B_(lever_arm_B) {
  if (!position_enu.allFinite() || !lever_arm_B.allFinite())
    throw Error("GpsPositionFactor: non-finite position or lever arm");
  sqrt_information_ = sqrt_information_of(covariance_enu, "GpsPositionFactor: the fix");
}

bool GpsPositionFactor::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  const SE3 T_W_B = pose_from_block(parameters[0]);
  const SE3 T_ENU_W = enu_alignment_from_block(parameters[1]);
  const Mat3 Rz = T_ENU_W.rotation();
  const Mat3 R_W_B = T_W_B.rotation();
  const Vec3 antenna_W = T_W_B.t + R_W_B * lever_arm_B_;
  const Vec3 antenna_enu = Rz * antenna_W + T_ENU_W.t;
  Eigen::Map<Vec3>{residuals} = sqrt_information_ * (antenna_enu - position_enu_);
  if (jacobians == nullptr) return true;

  if (jacobians[0]) {
    Eigen::Matrix<double, 3, 6> J;
    J.leftCols<3>() = Rz;
    J.rightCols<3>() = -Rz * R_W_B * hat(lever_arm_B_);
    write_pose_jacobian<3>(sqrt_information_ * J, parameters[0], jacobians[0]);
  }
  if (jacobians[1]) {
    Eigen::Matrix<double, 3, 4> J;
    J.col(0) = Vec3::UnitZ().cross(Rz * antenna_W);  // d Rz / d yaw = hat(e_z) Rz
    J.rightCols<3>() = Mat3::Identity();
    Eigen::Map<Eigen::Matrix<double, 3, 4, Eigen::RowMajor>>{jacobians[1]} = sqrt_information_ * J;
  }
  return true;
}

GpsPositionBiasFactor::GpsPositionBiasFactor(const Vec3& position_enu, const Mat3& covariance_enu,
                                             const Vec3& lever_arm_B)
    : position_(position_enu, covariance_enu, lever_arm_B) {}

bool GpsPositionBiasFactor::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  double* position_jacobians[2] = {jacobians ? jacobians[0] : nullptr, jacobians ? jacobians[1] : nullptr};
  if (!position_.Evaluate(parameters, residuals, jacobians ? position_jacobians : nullptr)) return false;
  // The bias adds to the predicted antenna position.
  const Mat3& L_inv = position_.sqrt_information();
  Eigen::Map<Vec3>{residuals} += L_inv * Eigen::Map<const Vec3>(parameters[2]);
  if (jacobians && jacobians[2]) Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>{jacobians[2]} = L_inv;
  return true;
}

}  // namespace navaid::estimation
