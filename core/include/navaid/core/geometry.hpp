#pragma once
// Rigid-body geometry on Eigen. Convention (DESIGN.md §4): T_A_B maps points from frame B into
// frame A, p_A = T_A_B * p_B. Quaternions are Hamilton, unit norm enforced on every update.
// Perturbations are on the right: R = R_hat * Exp(dtheta), T = T_hat * Exp(xi), xi = [rho; phi].
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace navaid {

using Vec3 = Eigen::Vector3d;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat3 = Eigen::Matrix3d;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Quat = Eigen::Quaterniond;

/// Gravity in the world frame W (gravity-aligned, z up; DESIGN.md §4) [m/s^2]: one value for the
/// simulator's IMU and the estimator's preintegration, so that they agree exactly.
inline const Vec3 kGravityW(0.0, 0.0, -9.81);

/// A rigid transform T_A_B: rotation q and translation t (p_A = q * p_B + t).
struct SE3 {
  Quat q = Quat::Identity();
  Vec3 t = Vec3::Zero();

  SE3() = default;
  SE3(const Quat& rotation, const Vec3& translation) : q(rotation.normalized()), t(translation) {}
  SE3(const Mat3& rotation, const Vec3& translation) : q(Quat(rotation).normalized()), t(translation) {}

  static SE3 identity() { return SE3(); }
  Mat3 rotation() const { return q.toRotationMatrix(); }
  Eigen::Matrix4d matrix() const {
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    m.topLeftCorner<3, 3>() = rotation();
    m.topRightCorner<3, 1>() = t;
    return m;
  }
  SE3 inverse() const {
    const Quat qi = q.conjugate();
    return SE3(qi, -(qi * t));
  }
  SE3 operator*(const SE3& other) const { return SE3(q * other.q, q * other.t + t); }
  Vec3 operator*(const Vec3& p) const { return q * p + t; }
  /// Same transform within tol (rotation angle [rad] and translation [m]); q and -q are equal.
  bool is_approx(const SE3& other, double tol = 1e-9) const {
    return (t - other.t).norm() <= tol && q.angularDistance(other.q) <= tol;
  }
};

// SO(3)
Mat3 hat(const Vec3& v);                     ///< skew-symmetric matrix, hat(a) b = a x b
Vec3 vee(const Mat3& m);                     ///< inverse of hat (uses the antisymmetric part)
Quat so3_exp(const Vec3& phi);               ///< rotation vector to unit quaternion
Vec3 so3_log(const Quat& q);                 ///< unit quaternion to rotation vector, |phi| <= pi
Mat3 so3_right_jacobian(const Vec3& phi);    ///< Jr(phi): Exp(phi + d) ~ Exp(phi) Exp(Jr d)
Mat3 so3_right_jacobian_inverse(const Vec3& phi);
Mat3 so3_left_jacobian(const Vec3& phi);     ///< Jl(phi) = Jr(-phi): Exp(phi + d) ~ Exp(Jl d) Exp(phi)
Mat3 so3_left_jacobian_inverse(const Vec3& phi);
Quat so3_boxplus(const Quat& q, const Vec3& dtheta);  ///< q * Exp(dtheta), normalized
Vec3 so3_boxminus(const Quat& a, const Quat& b);      ///< Log(b^-1 a)

// SE(3), tangent xi = [rho (translation part); phi (rotation part)]
SE3 se3_exp(const Vec6& xi);
Vec6 se3_log(const SE3& T);
SE3 se3_boxplus(const SE3& T, const Vec6& xi);    ///< T * Exp(xi)
Vec6 se3_boxminus(const SE3& a, const SE3& b);    ///< Log(b^-1 a)
Mat6 se3_adjoint(const SE3& T);                   ///< Ad_T for xi = [rho; phi]

/// Geodesic interpolation: alpha = 0 gives a, alpha = 1 gives b (rotation by slerp,
/// translation linear, i.e. interpolation on SO(3) x R^3 as trajectories are usually sampled).
SE3 interpolate(const SE3& a, const SE3& b, double alpha);

/// Roll-pitch-yaw (ZYX: R = Rz(yaw) Ry(pitch) Rx(roll)) helpers for human-facing output.
Vec3 rpy_from_quat(const Quat& q);
Quat quat_from_rpy(double roll, double pitch, double yaw);
double yaw_of(const Quat& q);
/// An angle [rad] wrapped to (-pi, pi].
double wrap_angle(double a);

}  // namespace navaid
