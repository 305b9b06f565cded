#include "navaid/estimation/factors/imu_factor.hpp"

#include <Eigen/Cholesky>

#include "navaid/core/errors.hpp"
#include "navaid/estimation/factors/pose_parametrization.hpp"

namespace navaid::estimation {

ImuFactor::ImuFactor(const ImuPreintegration& preintegration) : preintegration_(preintegration) {
  if (!(preintegration_.duration_s() > 0.0)) throw Error("ImuFactor: the preintegration spans no time");
  const Eigen::LLT<Mat15> llt(preintegration_.covariance());
  if (llt.info() != Eigen::Success) {
    throw Error("ImuFactor: preintegrated covariance is not positive definite (are all IMU noise densities zero?)");
  }
  sqrt_information_ = llt.matrixL().solve(Mat15::Identity());
}

bool ImuFactor::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  const ImuPreintegration& pre = preintegration_;
  const SE3 T_i = pose_from_block(parameters[0]);
  const SE3 T_j = pose_from_block(parameters[2]);
  const Eigen::Map<const Eigen::Matrix<double, 9, 1>> sb_i(parameters[1]);
  const Eigen::Map<const Eigen::Matrix<double, 9, 1>> sb_j(parameters[3]);
  const Vec3 v_i = sb_i.segment<3>(0), bg_i = sb_i.segment<3>(3), ba_i = sb_i.segment<3>(6);
  const Vec3 v_j = sb_j.segment<3>(0), bg_j = sb_j.segment<3>(3), ba_j = sb_j.segment<3>(6);
  const double dt = pre.duration_s();

  const Vec3 dbg = bg_i - pre.linearization_gyro_bias();
  const Vec3 phi_bg = pre.d_theta_d_bg() * dbg;
  const Quat gamma = pre.delta_q() * so3_exp(phi_bg);
  const Mat3 R_i_T = T_i.rotation().transpose();
  const Vec3 dp = T_j.t - T_i.t - v_i * dt - 0.5 * kGravityW * dt * dt;
  const Vec3 dv = v_j - v_i - kGravityW * dt;
  const Quat E = gamma.conjugate() * T_i.q.conjugate() * T_j.q;

  Eigen::Matrix<double, 15, 1> r;
  r.segment<3>(kTheta) = so3_log(E);
  r.segment<3>(kAlpha) = R_i_T * dp - pre.corrected_delta_p(bg_i, ba_i);
  r.segment<3>(kBeta) = R_i_T * dv - pre.corrected_delta_v(bg_i, ba_i);
  r.segment<3>(kBiasGyro) = bg_j - bg_i;
  r.segment<3>(kBiasAccel) = ba_j - ba_i;
  Eigen::Map<Eigen::Matrix<double, 15, 1>>{residuals} = sqrt_information_ * r;
  if (jacobians == nullptr) return true;

  const Mat3 I = Mat3::Identity();
  const Mat3 Jr_inv = so3_right_jacobian_inverse(r.segment<3>(kTheta));
  using Mat15x6 = Eigen::Matrix<double, 15, 6>;
  using Mat15x9 = Eigen::Matrix<double, 15, 9>;
  if (jacobians[0] != nullptr) {  // pose_i: [dp_i, dtheta_i]
    Mat15x6 J = Mat15x6::Zero();
    J.block<3, 3>(kAlpha, 0) = -R_i_T;
    J.block<3, 3>(kTheta, 3) = -Jr_inv * (T_j.q.conjugate() * T_i.q).toRotationMatrix();
    J.block<3, 3>(kAlpha, 3) = hat(R_i_T * dp);
    J.block<3, 3>(kBeta, 3) = hat(R_i_T * dv);
    write_pose_jacobian<15>(sqrt_information_ * J, parameters[0], jacobians[0]);
  }
  if (jacobians[1] != nullptr) {  // speed_bias_i: [v_i, bg_i, ba_i]
    Mat15x9 J = Mat15x9::Zero();
    J.block<3, 3>(kAlpha, 0) = -R_i_T * dt;
    J.block<3, 3>(kBeta, 0) = -R_i_T;
    // gamma(b) = gamma_hat Exp(J_g db): its error rotates E by -E^T Jr(phi) J_g on the right.
    J.block<3, 3>(kTheta, 3) =
        -Jr_inv * E.toRotationMatrix().transpose() * so3_right_jacobian(phi_bg) * pre.d_theta_d_bg();
    J.block<3, 3>(kAlpha, 3) = -pre.d_alpha_d_bg();
    J.block<3, 3>(kBeta, 3) = -pre.d_beta_d_bg();
    J.block<3, 3>(kAlpha, 6) = -pre.d_alpha_d_ba();
    J.block<3, 3>(kBeta, 6) = -pre.d_beta_d_ba();
    J.block<3, 3>(kBiasGyro, 3) = -I;
    J.block<3, 3>(kBiasAccel, 6) = -I;
    Eigen::Map<Eigen::Matrix<double, 15, 9, Eigen::RowMajor>>{jacobians[1]} = sqrt_information_ * J;
  }
  if (jacobians[2] != nullptr) {  // pose_j
    Mat15x6 J = Mat15x6::Zero();
    J.block<3, 3>(kAlpha, 0) = R_i_T;
    J.block<3, 3>(kTheta, 3) = Jr_inv;
    write_pose_jacobian<15>(sqrt_information_ * J, parameters[2], jacobians[2]);
  }
  if (jacobians[3] != nullptr) {  // speed_bias_j
    Mat15x9 J = Mat15x9::Zero();
    J.block<3, 3>(kBeta, 0) = R_i_T;
    J.block<3, 3>(kBiasGyro, 3) = I;
    J.block<3, 3>(kBiasAccel, 6) = I;
    Eigen::Map<Eigen::Matrix<double, 15, 9, Eigen::RowMajor>>{jacobians[3]} = sqrt_information_ * J;
  }
  return true;
}

}  // namespace navaid::estimation
