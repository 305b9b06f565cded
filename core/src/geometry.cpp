#include "navaid/core/geometry.hpp"

#include <cmath>

namespace navaid {
namespace {

// Below this angle the closed forms of the Jacobian coefficients lose digits to cancellation
// (error ~ eps / theta^2); the series kept here is accurate to < 1e-17 there.
constexpr double kSeriesAngle = 0.1;

// (1 - cos t) / t^2 and (t - sin t) / t^3, the two coefficients shared by Jl and Jr.
void jacobian_coefficients(double theta, double* a, double* b) {
  const double t2 = theta * theta;
  if (theta < kSeriesAngle) {
    *a = 0.5 - t2 * (1.0 / 24 - t2 * (1.0 / 720 - t2 * (1.0 / 40320 - t2 / 3628800)));
    *b = 1.0 / 6 - t2 * (1.0 / 120 - t2 * (1.0 / 5040 - t2 * (1.0 / 362880 - t2 / 39916800)));
  } else {
    *a = (1.0 - std::cos(theta)) / t2;
    *b = (theta - std::sin(theta)) / (t2 * theta);
  }
}

// 1/t^2 - (1 + cos t) / (2 t sin t), the hat^2 coefficient of the inverse Jacobians. The
// half-angle form stays finite at t = pi where the textbook form is 0/0.
double inverse_jacobian_coefficient(double theta) {
  const double t2 = theta * theta;
  if (theta < kSeriesAngle) return 1.0 / 12 + t2 * (1.0 / 720 + t2 * (1.0 / 30240 + t2 / 1209600));
  const double half = 0.5 * theta;
  return 1.0 / t2 - std::cos(half) / (2.0 * theta * std::sin(half));
}

}  // namespace

Mat3 hat(const Vec3& v) {
  Mat3 m;
  m << 0, -v.z(), v.y(),  //
      v.z(), 0, -v.x(),   //
      -v.y(), v.x(), 0;
  return m;
}

Vec3 vee(const Mat3& m) {
  return 0.5 * Vec3(m(2, 1) - m(1, 2), m(0, 2) - m(2, 0), m(1, 0) - m(0, 1));
}

Quat so3_exp(const Vec3& phi) {
  const double theta = phi.norm();
  // sin(theta/2)/theta without the 0/0 at the identity.
  const double t2 = theta * theta;
  const double s = theta < 1e-4 ? 0.5 - t2 / 48 + t2 * t2 / 3840 : std::sin(0.5 * theta) / theta;
  Quat q(std::cos(0.5 * theta), s * phi.x(), s * phi.y(), s * phi.z());
  q.normalize();
  return q;
}

Vec3 so3_log(const Quat& q_in) {
  // q and -q are the same rotation; pick w >= 0 so that the angle is in [0, pi].
  const double sign = q_in.w() < 0 ? -1.0 : 1.0;
  const double w = sign * q_in.w();
  const Vec3 v = sign * q_in.vec();
  const double n = v.norm();
  // angle = 2 atan2(n, w) is well conditioned everywhere, including near pi (w -> 0), and
  // scale-free, so a slightly non-unit input is tolerated.
  double scale;
  if (n < 1e-8 * w) {
    const double r2 = (n * n) / (w * w);
    scale = 2.0 / w * (1.0 - r2 / 3.0);  // series of 2 atan(n/w)/n
  } else {
    scale = 2.0 * std::atan2(n, w) / n;
  }
  return scale * v;
}

Mat3 so3_right_jacobian(const Vec3& phi) {
  double a, b;
  jacobian_coefficients(phi.norm(), &a, &b);
  const Mat3 H = hat(phi);
  return Mat3::Identity() - a * H + b * H * H;
}

Mat3 so3_right_jacobian_inverse(const Vec3& phi) {
  const Mat3 H = hat(phi);
  return Mat3::Identity() + 0.5 * H + inverse_jacobian_coefficient(phi.norm()) * H * H;
}

Mat3 so3_left_jacobian(const Vec3& phi) {
  double a, b;
  jacobian_coefficients(phi.norm(), &a, &b);
  const Mat3 H = hat(phi);
  return Mat3::Identity() + a * H + b * H * H;
}

Mat3 so3_left_jacobian_inverse(const Vec3& phi) {
  const Mat3 H = hat(phi);
  return Mat3::Identity() - 0.5 * H + inverse_jacobian_coefficient(phi.norm()) * H * H;
}

Quat so3_boxplus(const Quat& q, const Vec3& dtheta) {
  Quat r = q * so3_exp(dtheta);
  r.normalize();
  return r;
}

Vec3 so3_boxminus(const Quat& a, const Quat& b) { return so3_log(b.conjugate() * a); }

SE3 se3_exp(const Vec6& xi) {
  const Vec3 rho = xi.head<3>();
  const Vec3 phi = xi.tail<3>();
  return SE3(so3_exp(phi), so3_left_jacobian(phi) * rho);
}

Vec6 se3_log(const SE3& T) {
  const Vec3 phi = so3_log(T.q);
  Vec6 xi;
  xi << so3_left_jacobian_inverse(phi) * T.t, phi;
  return xi;
}

SE3 se3_boxplus(const SE3& T, const Vec6& xi) { return T * se3_exp(xi); }

Vec6 se3_boxminus(const SE3& a, const SE3& b) { return se3_log(b.inverse() * a); }

Mat6 se3_adjoint(const SE3& T) {
  const Mat3 R = T.rotation();
  Mat6 ad;
  ad << R, hat(T.t) * R,  //
      Mat3::Zero(), R;
  return ad;
}

SE3 interpolate(const SE3& a, const SE3& b, double alpha) {
  // Through the log rather than Eigen's slerp so the shortest arc (|angle| <= pi) is explicit.
  const Vec3 dphi = so3_boxminus(b.q, a.q);
  return SE3(so3_boxplus(a.q, alpha * dphi), (1.0 - alpha) * a.t + alpha * b.t);
}

Vec3 rpy_from_quat(const Quat& q) {
  const Mat3 R = q.normalized().toRotationMatrix();
  const double cos_pitch = std::hypot(R(0, 0), R(1, 0));
  const double pitch = std::atan2(-R(2, 0), cos_pitch);  // better than asin near +-pi/2
  if (cos_pitch < 1e-10) {
    // Gimbal lock: only roll -+ yaw is observable; report it all as yaw with zero roll.
    return Vec3(0.0, pitch, std::atan2(-R(0, 1), R(1, 1)));
  }
  return Vec3(std::atan2(R(2, 1), R(2, 2)), pitch, std::atan2(R(1, 0), R(0, 0)));
}

Quat quat_from_rpy(double roll, double pitch, double yaw) {
  Quat q = Quat(Eigen::AngleAxisd(yaw, Vec3::UnitZ())) * Quat(Eigen::AngleAxisd(pitch, Vec3::UnitY())) *
           Quat(Eigen::AngleAxisd(roll, Vec3::UnitX()));
  q.normalize();
  return q;
}

double yaw_of(const Quat& q) { return rpy_from_quat(q).z(); }

double wrap_angle(double a) {
  a = std::remainder(a, 2.0 * M_PI);
  return a <= -M_PI ? a + 2.0 * M_PI : a;
}

}  // namespace navaid
