#include "navaid/estimation/state_prior_factor.hpp"

#include <Eigen/Cholesky>

#include "navaid/core/errors.hpp"
#include "navaid/estimation/factors/pose_parametrization.hpp"

namespace navaid::estimation {

StatePriorFactor::StatePriorFactor(const SE3& T_W_B, const Vec3& v_W, const Vec3& b_g, const Vec3& b_a,
                                   const Mat15& covariance)
    : T_W_B_(T_W_B) {
  speed_bias_ << v_W, b_g, b_a;
  const Eigen::LLT<Mat15> llt(0.5 * (covariance + covariance.transpose()));
  if (llt.info() != Eigen::Success || !covariance.allFinite())
    throw Error("state prior: covariance is not symmetric positive definite");
  sqrt_information_ = llt.matrixL().solve(Mat15::Identity());
}

bool StatePriorFactor::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  const SE3 T = pose_from_block(parameters[0]);
  const Eigen::Map<const Eigen::Matrix<double, 9, 1>> sb(parameters[1]);
  Eigen::Matrix<double, 15, 1> e;
  const Vec3 r_theta = so3_log(T_W_B_.q.conjugate() * T.q);
  e << r_theta, T.t - T_W_B_.t, sb - speed_bias_;
  Eigen::Map<Eigen::Matrix<double, 15, 1>>{residuals} = sqrt_information_ * e;
  if (!jacobians) return true;
  if (jacobians[0]) {
    Eigen::Matrix<double, 15, 6> J = Eigen::Matrix<double, 15, 6>::Zero();  // tangent [dp, dtheta]
    J.block<3, 3>(3, 0).setIdentity();
    J.block<3, 3>(0, 3) = so3_right_jacobian_inverse(r_theta);
    write_pose_jacobian<15>(sqrt_information_ * J, parameters[0], jacobians[0]);
  }
  if (jacobians[1]) {
    Eigen::Map<Eigen::Matrix<double, 15, 9, Eigen::RowMajor>> J(jacobians[1]);
    J = sqrt_information_.rightCols<9>();
  }
  return true;
}

}  // namespace navaid::estimation
