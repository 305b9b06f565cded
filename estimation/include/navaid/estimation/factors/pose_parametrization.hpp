#pragma once
// How the estimator's states are laid out in Ceres parameter blocks, and the manifolds they live on.
//
//   pose        [p_x p_y p_z  q_x q_y q_z q_w]   T_W_B (or T_B_C): translation, Eigen quaternion
//   speed_bias  [v_W (3)  b_g (3)  b_a (3)]      same order as StateEstimate's covariance
//   T_ENU_W     [yaw  t_x t_y t_z]               4-DOF: gravity fixes roll and pitch
//   inverse depth  [lambda]                       1 / z of a feature in its anchor camera
//
// The pose manifold is Ceres' ProductManifold<EuclideanManifold<3>, EigenQuaternionManifold>:
// tangent [dp (3), d (3)] with q (+) d = [cos|d|, sin|d| d/|d|] * q = Exp(2 d) * q, i.e. a rotation
// error on the LEFT (world frame) whose rotation vector is 2 d. Covariances that Ceres computes in
// this tangent convert to StateEstimate's right error as dtheta_right = 2 R^T d.
//
// Factors return true ambient Jacobians (w.r.t. the 7 numbers), computed from their derivative
// with respect to a right perturbation q * Exp(dtheta) by lift_rotation_jacobian(). Residuals
// normalize q first, so the Jacobian has no component along q itself and Ceres' chain rule
// J_ambient * PlusJacobian gives the exact tangent Jacobian for any quaternion manifold.
#include <memory>

#include <Eigen/Core>
#include <ceres/manifold.h>
#include <ceres/product_manifold.h>

#include "navaid/core/geometry.hpp"

namespace navaid::estimation {

constexpr int kPoseSize = 7;
constexpr int kPoseTangentSize = 6;
constexpr int kSpeedBiasSize = 9;
constexpr int kEnuAlignmentSize = 4;

using PoseManifold = ceres::ProductManifold<ceres::EuclideanManifold<3>, ceres::EigenQuaternionManifold>;

/// A manifold for a pose parameter block (hand it to ceres::Problem::SetManifold).
std::unique_ptr<ceres::Manifold> make_pose_manifold();

/// Writes T into a 7-double pose block.
void pose_to_block(const SE3& T, double* block);
/// Reads a 7-double pose block; the quaternion is normalized.
SE3 pose_from_block(const double* block);

/// T_ENU_W = (Rz(yaw), t) from an alignment block [yaw, t_x, t_y, t_z].
SE3 enu_alignment_from_block(const double* block);

/// Ambient Jacobian (rows x 4, columns q_x q_y q_z q_w) of a residual r(q / |q|) whose derivative
/// w.r.t. a right perturbation q * Exp(dtheta) is J_theta (rows x 3). q must be unit.
/// J_ambient = 4 J_theta M^T with M = d(q * Exp(dtheta))/d(dtheta) (M^T M = I / 4, M^T q = 0).
template <int Rows>
Eigen::Matrix<double, Rows, 4> lift_rotation_jacobian(const Eigen::Matrix<double, Rows, 3>& J_theta,
                                                      const Quat& q) {
  Eigen::Matrix<double, 4, 3> M;
  M.topRows<3>() = q.w() * Mat3::Identity() + hat(q.vec());
  M.row(3) = -q.vec().transpose();
  M *= 0.5;
  return 4.0 * J_theta * M.transpose();
}

/// Writes the ambient Jacobian (Rows x 7, row-major as Ceres wants) of a residual whose derivative
/// w.r.t. the tangent [dp, dtheta] (right perturbation) of a pose block is J_tangent.
template <int Rows>
void write_pose_jacobian(const Eigen::Matrix<double, Rows, 6>& J_tangent, const double* pose, double* jacobian) {
  Eigen::Map<Eigen::Matrix<double, Rows, kPoseSize, Eigen::RowMajor>> J(jacobian);
  const Eigen::Map<const Quat> q(pose + 3);
  J.template leftCols<3>() = J_tangent.template leftCols<3>();
  // The residual sees q / |q|: the 1 / |q| keeps the Jacobian exact off the unit sphere too.
  J.template rightCols<4>() =
      lift_rotation_jacobian<Rows>(J_tangent.template rightCols<3>(), q.normalized()) / q.norm();
}

}  // namespace navaid::estimation
