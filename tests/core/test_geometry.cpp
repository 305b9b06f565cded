#include "navaid/core/geometry.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include <unsupported/Eigen/MatrixFunctions>

#include "navaid/core/random_draws.hpp"

namespace navaid {
namespace {


// Rotation vectors covering the hard regimes: identity, tiny, the series/closed-form switch
// (0.1 rad), generic, and just below pi.
std::vector<Vec3> test_rotation_vectors() {
  const Vec3 axis = Vec3(0.3, -0.5, 0.81).normalized();
  std::vector<Vec3> out{Vec3::Zero()};
  for (double angle : {1e-15, 1e-9, 1e-6, 1e-4, 0.0999999, 0.1, 0.1000001, 0.5, 1.0, 2.0, 3.0, M_PI - 1e-4,
                       M_PI - 1e-9}) {
    out.push_back(angle * axis);
    out.push_back(angle * Vec3::UnitX());
  }
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 20; ++i) {
    const Vec3 dir = draw_vector<3>([&] { return u(rng); }).normalized();
    out.push_back(dir * (M_PI * 0.5 * (u(rng) + 1.0)));
  }
  return out;
}

Vec6 random_twist(std::mt19937& rng, double max_angle) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Vec6 xi;
  xi.head<3>() << 2.0 * u(rng), 2.0 * u(rng), 2.0 * u(rng);
  // The angle before the axis, GCC's order for Eigen's operator* operands: the order of record
  // (random_draws.hpp).
  const double angle_scale = u(rng) + 1.0;
  xi.tail<3>() = draw_vector<3>([&] { return u(rng); }).normalized() * max_angle * 0.5 * angle_scale;
  return xi;
}

Eigen::Matrix4d twist_matrix(const Vec6& xi) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
  m.topLeftCorner<3, 3>() = hat(xi.tail<3>());
  m.topRightCorner<3, 1>() = xi.head<3>();
  return m;
}

TEST(Geometry, HatIsCrossProductAndVeeInvertsIt) {
  const Vec3 a(0.3, -1.2, 2.5), b(-0.7, 0.4, 1.1);
  EXPECT_TRUE((hat(a) * b).isApprox(a.cross(b), 1e-15));
  EXPECT_TRUE(vee(hat(a)).isApprox(a, 1e-15));
  EXPECT_TRUE((hat(a) + hat(a).transpose()).isZero(0.0));
  // vee keeps only the antisymmetric part.
  EXPECT_TRUE(vee(hat(a) + Mat3::Identity() * 5.0).isApprox(a, 1e-15));
}

TEST(Geometry, So3ExpMatchesMatrixExponential) {
  for (const Vec3& phi : test_rotation_vectors()) {
    const Mat3 expected = hat(phi).exp();
    const Quat q = so3_exp(phi);
    EXPECT_NEAR(q.norm(), 1.0, 1e-15);
    EXPECT_TRUE(q.toRotationMatrix().isApprox(expected, 1e-12)) << phi.transpose();
  }
}

TEST(Geometry, So3ExpLogRoundTrip) {
  for (const Vec3& phi : test_rotation_vectors()) {
    const Vec3 back = so3_log(so3_exp(phi));
    EXPECT_LT((back - phi).norm(), 1e-12 * std::max(1.0, phi.norm())) << phi.transpose();
  }
}

TEST(Geometry, So3LogIgnoresQuaternionSignAndStaysWithinPi) {
  for (const Vec3& phi : test_rotation_vectors()) {
    const Quat q = so3_exp(phi);
    const Quat minus_q(-q.w(), -q.x(), -q.y(), -q.z());
    EXPECT_LT((so3_log(minus_q) - so3_log(q)).norm(), 1e-12);
  }
  // A rotation vector longer than pi comes back as the equivalent short one.
  const Vec3 axis = Vec3(1, 2, -2).normalized();
  const Vec3 back = so3_log(so3_exp(4.0 * axis));
  EXPECT_LT((back - (4.0 - 2 * M_PI) * axis).norm(), 1e-12);
  EXPECT_LE(back.norm(), M_PI);
}

TEST(Geometry, So3LogExactlyPi) {
  // At pi the axis sign is ambiguous; either answer must be the same rotation with |phi| = pi.
  for (const Vec3& axis : {Vec3(Vec3::UnitX()), Vec3(Vec3(1, -1, 0.5).normalized())}) {
    const Quat q(Eigen::AngleAxisd(M_PI, axis));
    const Vec3 phi = so3_log(q);
    EXPECT_NEAR(phi.norm(), M_PI, 1e-12);
    EXPECT_LT(so3_exp(phi).angularDistance(q), 1e-12);
  }
}

TEST(Geometry, So3LogTinyAngleKeepsRelativePrecision) {
  const Vec3 phi(3e-12, -1e-12, 2e-12);
  const Vec3 back = so3_log(so3_exp(phi));
  EXPECT_LT((back - phi).norm(), 1e-10 * phi.norm());
}

// Central differences of a function R^3 -> R^3 given as boxminus(f(x + d), f(x)).
template <typename F>
Mat3 numeric_jacobian3(F f, double h = 1e-6) {
  Mat3 J;
  for (int i = 0; i < 3; ++i) {
    const Vec3 d = Vec3::Unit(i) * h;
    J.col(i) = (f(d) - f(-d)) / (2 * h);
  }
  return J;
}

TEST(Geometry, So3RightJacobianMatchesNumeric) {
  for (const Vec3& phi : test_rotation_vectors()) {
    if (phi.norm() > M_PI - 1e-3) continue;  // the log wraps within h of pi
    const Quat R = so3_exp(phi);
    // Exp(phi + d) = Exp(phi) Exp(Jr d)  =>  Jr = d Log(Exp(phi)^-1 Exp(phi + d)) / dd.
    const Mat3 numeric = numeric_jacobian3([&](const Vec3& d) { return so3_boxminus(so3_exp(phi + d), R); });
    EXPECT_TRUE(so3_right_jacobian(phi).isApprox(numeric, 1e-8)) << phi.transpose();
    const Mat3 numeric_left =
        numeric_jacobian3([&](const Vec3& d) { return so3_log(so3_exp(phi + d) * R.conjugate()); });
    EXPECT_TRUE(so3_left_jacobian(phi).isApprox(numeric_left, 1e-8)) << phi.transpose();
  }
}

TEST(Geometry, So3JacobianIdentities) {
  for (const Vec3& phi : test_rotation_vectors()) {
    const Mat3 Jr = so3_right_jacobian(phi);
    const Mat3 Jl = so3_left_jacobian(phi);
    EXPECT_TRUE((so3_right_jacobian_inverse(phi) * Jr).isIdentity(1e-9)) << phi.transpose();
    EXPECT_TRUE((so3_left_jacobian_inverse(phi) * Jl).isIdentity(1e-9)) << phi.transpose();
    EXPECT_TRUE(Jl.isApprox(so3_right_jacobian(-phi), 1e-14));
    EXPECT_TRUE(Jl.isApprox(so3_exp(phi).toRotationMatrix() * Jr, 1e-12));
  }
  // The inverse stays finite at pi, where the textbook formula is 0/0.
  EXPECT_TRUE(so3_right_jacobian_inverse(M_PI * Vec3::UnitZ()).allFinite());
}

TEST(Geometry, So3BoxplusJacobianMatchesNumeric) {
  const Quat q = so3_exp(Vec3(0.4, -1.1, 0.3));
  const Vec3 delta(0.2, 0.5, -0.9);
  const Quat q1 = so3_boxplus(q, delta);
  // Perturbing the tangent argument of boxplus: (q1)^-1 boxplus(q, delta + d) = Exp(Jr(delta) d).
  const Mat3 d_delta = numeric_jacobian3([&](const Vec3& d) { return so3_boxminus(so3_boxplus(q, delta + d), q1); });
  EXPECT_TRUE(so3_right_jacobian(delta).isApprox(d_delta, 1e-8));
  // Perturbing the result: boxminus(q1 Exp(d), q) = Log(Exp(delta) Exp(d)) moves by Jr^-1(delta) d.
  const Mat3 d_result = numeric_jacobian3([&](const Vec3& d) { return so3_boxminus(so3_boxplus(q1, d), q); });
  EXPECT_TRUE(so3_right_jacobian_inverse(delta).isApprox(d_result, 1e-8));
  // boxminus undoes boxplus and boxplus stays unit norm.
  EXPECT_TRUE(so3_boxminus(so3_boxplus(q, delta), q).isApprox(delta, 1e-13));
  EXPECT_NEAR(so3_boxplus(q, delta).norm(), 1.0, 1e-15);
}

TEST(Geometry, Se3ExpMatchesMatrixExponential) {
  std::mt19937 rng(7);
  for (double max_angle : {0.0, 1e-9, 1e-3, 1.0, 3.1}) {
    for (int i = 0; i < 10; ++i) {
      const Vec6 xi = random_twist(rng, max_angle);
      EXPECT_TRUE(se3_exp(xi).matrix().isApprox(twist_matrix(xi).exp(), 1e-12)) << xi.transpose();
    }
  }
}

TEST(Geometry, Se3ExpLogRoundTrip) {
  std::mt19937 rng(11);
  for (double max_angle : {0.0, 1e-12, 1e-6, 0.1, 1.0, 3.0, M_PI - 1e-6}) {
    for (int i = 0; i < 10; ++i) {
      const Vec6 xi = random_twist(rng, max_angle);
      EXPECT_TRUE((se3_log(se3_exp(xi)) - xi).isZero(1e-9)) << xi.transpose();
      const SE3 T = se3_exp(xi);
      EXPECT_TRUE(se3_exp(se3_log(T)).is_approx(T, 1e-12));
    }
  }
  // Near pi the rotation part is well conditioned; translation goes through Jl^-1, finite at pi.
  Vec6 xi;
  xi << 0.5, -1.0, 2.0, 0, 0, M_PI - 1e-9;
  EXPECT_TRUE((se3_log(se3_exp(xi)) - xi).isZero(1e-7));
}

TEST(Geometry, Se3BoxplusBoxminus) {
  std::mt19937 rng(3);
  const SE3 T = se3_exp(random_twist(rng, 2.0));
  const Vec6 xi = random_twist(rng, 1.0);
  EXPECT_TRUE(se3_boxplus(T, xi).is_approx(T * se3_exp(xi), 1e-14));
  EXPECT_TRUE((se3_boxminus(se3_boxplus(T, xi), T) - xi).isZero(1e-12));
  EXPECT_TRUE(se3_boxminus(T, T).isZero(1e-15));
  // Perturbations are on the right: T * Exp(xi) differs from Exp(xi) * T.
  EXPECT_FALSE(se3_boxplus(T, xi).is_approx(se3_exp(xi) * T, 1e-6));
}

TEST(Geometry, Se3AdjointIdentity) {
  std::mt19937 rng(5);
  for (int i = 0; i < 20; ++i) {
    const SE3 T = se3_exp(random_twist(rng, 3.0));
    const Vec6 xi = random_twist(rng, 1.5);
    const SE3 lhs = se3_exp(se3_adjoint(T) * xi);
    const SE3 rhs = T * se3_exp(xi) * T.inverse();
    EXPECT_TRUE(lhs.is_approx(rhs, 1e-11));
  }
  EXPECT_TRUE(se3_adjoint(SE3()).isIdentity(0.0));
}

TEST(Geometry, InterpolateEndpointsAndMidpoint) {
  const SE3 a(so3_exp(Vec3(0.1, 0.2, -0.3)), Vec3(1, 2, 3));
  const SE3 b(so3_exp(Vec3(-0.5, 0.9, 1.2)), Vec3(-3, 0, 5));
  EXPECT_TRUE(interpolate(a, b, 0.0).is_approx(a, 1e-14));
  EXPECT_TRUE(interpolate(a, b, 1.0).is_approx(b, 1e-14));
  const SE3 mid = interpolate(a, b, 0.5);
  EXPECT_TRUE(mid.t.isApprox(Vec3(-1, 1, 4), 1e-15));
  // The midpoint rotation is equally far from both ends, half the total angle.
  const double total = a.q.angularDistance(b.q);
  EXPECT_NEAR(mid.q.angularDistance(a.q), 0.5 * total, 1e-12);
  EXPECT_NEAR(mid.q.angularDistance(b.q), 0.5 * total, 1e-12);
  // The sign of b's quaternion must not send the interpolation the long way round.
  const SE3 b_flipped(Quat(-b.q.w(), -b.q.x(), -b.q.y(), -b.q.z()), b.t);
  EXPECT_TRUE(interpolate(a, b_flipped, 0.5).is_approx(mid, 1e-12));
}

TEST(Geometry, RpyRoundTripAndConvention) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 50; ++i) {
    const Vec3 rpy = draw_vector<3>([&] { return u(rng); }).cwiseProduct(Vec3(M_PI, 0.5 * M_PI, M_PI));
    const Quat q = quat_from_rpy(rpy.x(), rpy.y(), rpy.z());
    EXPECT_TRUE(rpy_from_quat(q).isApprox(rpy, 1e-12)) << rpy.transpose();
    EXPECT_NEAR(yaw_of(q), rpy.z(), 1e-12);
  }
  // ZYX: R = Rz(yaw) Ry(pitch) Rx(roll).
  const Mat3 R = (Eigen::AngleAxisd(0.3, Vec3::UnitZ()) * Eigen::AngleAxisd(-0.2, Vec3::UnitY()) *
                  Eigen::AngleAxisd(0.1, Vec3::UnitX()))
                     .toRotationMatrix();
  EXPECT_TRUE(quat_from_rpy(0.1, -0.2, 0.3).toRotationMatrix().isApprox(R, 1e-15));
  // A pure yaw of 90 degrees turns the x axis into y (z up).
  EXPECT_TRUE((quat_from_rpy(0, 0, M_PI / 2) * Vec3::UnitX()).isApprox(Vec3::UnitY(), 1e-15));
}

TEST(Geometry, RpyAtGimbalLockIsConsistent) {
  for (double pitch : {M_PI / 2, -M_PI / 2}) {
    const Quat q = quat_from_rpy(0.4, pitch, -1.1);
    const Vec3 rpy = rpy_from_quat(q);
    EXPECT_TRUE(rpy.allFinite());
    EXPECT_NEAR(rpy.y(), pitch, 1e-7);
    // Only roll -+ yaw is defined there; the returned angles must rebuild the same rotation.
    EXPECT_LT(quat_from_rpy(rpy.x(), rpy.y(), rpy.z()).angularDistance(q), 1e-7);
  }
}

}  // namespace
}  // namespace navaid
