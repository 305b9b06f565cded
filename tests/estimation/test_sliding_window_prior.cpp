// StatePriorFactor: the Gaussian prior on one window state (initial state, pinned gauge).
#include "navaid/estimation/state_prior_factor.hpp"

#include <gtest/gtest.h>

#include "factor_check.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/estimation/factors/pose_parametrization.hpp"
#include "test_support.hpp"

namespace navaid::estimation {
namespace {

Mat15 random_covariance(std::mt19937_64& rng) {
  Eigen::Matrix<double, 15, 15> A;
  std::normal_distribution<double> n(0.0, 0.1);
  for (int i = 0; i < 15; ++i)
    for (int j = 0; j < 15; ++j) A(i, j) = n(rng);
  return A * A.transpose() + 0.01 * Mat15::Identity();
}

TEST(StatePriorFactor, JacobiansMatchNumericOnTheManifolds) {
  std::mt19937_64 rng(11);
  const auto manifold = make_pose_manifold();
  for (int trial = 0; trial < 5; ++trial) {
    const SE3 T0 = testing::random_pose(rng);
    // Drawn last argument first: the order of record (random_draws.hpp).
    const Mat15 covariance = random_covariance(rng);
    const Vec3 b_a = testing::random_vector(rng, 0.1), b_g = testing::random_vector(rng, 0.1);
    const StatePriorFactor f(T0, testing::random_vector(rng, 1), b_g, b_a, covariance);
    double pose[7], sb[9];
    const Vec3 t = testing::random_vector(rng, 0.3);
    pose_to_block(T0 * SE3(testing::random_rotation(rng, 0.5), t), pose);
    for (double& x : sb) x = std::normal_distribution<double>(0, 0.5)(rng);
    EXPECT_TRUE(testing::jacobians_match(f, {pose, sb}, {manifold.get(), nullptr}));
  }
}

TEST(StatePriorFactor, ResidualIsTheWhitenedRightErrorInStateEstimateOrder) {
  // Diagonal covariance: each residual is the error component over its sigma.
  Mat15 P = Mat15::Zero();
  Eigen::Matrix<double, 15, 1> sigma;
  sigma << 0.1, 0.2, 0.3, 1, 2, 3, 0.5, 0.5, 0.5, 0.01, 0.02, 0.03, 0.1, 0.2, 0.3;
  P.diagonal() = sigma.cwiseAbs2();
  const SE3 T0(quat_from_rpy(0.1, -0.2, 0.3), Vec3(1, 2, 3));
  const StatePriorFactor f(T0, Vec3(0.1, 0, 0), Vec3::Zero(), Vec3::Zero(), P);
  const Vec3 dtheta(0.01, -0.02, 0.03), dp(0.5, -1, 2);
  double pose[7], sb[9] = {0.6, 0, 0, 0.01, 0, 0, 0, 0, -0.3};
  pose_to_block(SE3(T0.q * so3_exp(dtheta), T0.t + dp), pose);
  const double* blocks[] = {pose, sb};
  Eigen::Matrix<double, 15, 1> r;
  ASSERT_TRUE(f.Evaluate(blocks, r.data(), nullptr));
  Eigen::Matrix<double, 15, 1> expected;
  expected << dtheta, dp, 0.5, 0, 0, 0.01, 0, 0, 0, 0, -0.3;
  EXPECT_LT((r - expected.cwiseQuotient(sigma)).norm(), 1e-9) << r.transpose();
}

TEST(StatePriorFactor, RejectsACovarianceThatIsNotPositiveDefinite) {
  Mat15 P = Mat15::Identity();
  P(4, 4) = -1;
  navaid::testing::expect_throw<Error>([&] { StatePriorFactor(SE3(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), P); },
                               "negative variance");
}

}  // namespace
}  // namespace navaid::estimation
