#include "navaid/estimation/factors/pose_parametrization.hpp"

#include <gtest/gtest.h>

#include <random>

#include "factor_check.hpp"

namespace navaid::estimation {
namespace {

TEST(PoseParametrization, BlockRoundTripAndManifoldSizes) {
  std::mt19937_64 rng(5);
  const SE3 T = testing::random_pose(rng);
  double block[kPoseSize];
  pose_to_block(T, block);
  EXPECT_TRUE(pose_from_block(block).is_approx(T, 1e-15));
  const auto m = make_pose_manifold();
  EXPECT_EQ(m->AmbientSize(), kPoseSize);
  EXPECT_EQ(m->TangentSize(), kPoseTangentSize);
}

TEST(PoseParametrization, LiftedJacobianIsExactForCeresLeftPerturbation) {
  // For r(q) = R(q) v: d r / d(right dtheta) = -R hat(v). Through the lift and Ceres' own
  // PlusJacobian (q (+) d = [cos|d|, sin|d| d/|d|] q, a left rotation by the vector 2 d) it must
  // become d r / d d = -2 hat(R v), and the lifted Jacobian must be blind to scaling q.
  std::mt19937_64 rng(6);
  const ceres::EigenQuaternionManifold manifold;
  for (int trial = 0; trial < 10; ++trial) {
    const Quat q = testing::random_rotation(rng);
    const Vec3 v = testing::random_vector(rng, 2.0);
    const Mat3 R = q.toRotationMatrix();
    const Eigen::Matrix<double, 3, 4> J = lift_rotation_jacobian<3>(-R * hat(v), q);
    Eigen::Matrix<double, 4, 3, Eigen::RowMajor> plus;
    ASSERT_TRUE(manifold.PlusJacobian(q.coeffs().data(), plus.data()));
    EXPECT_LT((J * plus + 2.0 * hat(R * v)).norm(), 1e-13);
    EXPECT_LT((J * q.coeffs()).norm(), 1e-13);
  }
}

}  // namespace
}  // namespace navaid::estimation
