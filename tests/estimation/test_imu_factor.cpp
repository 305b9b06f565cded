#include "navaid/estimation/factors/imu_factor.hpp"

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include <ceres/ceres.h>

#include "factor_check.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/estimation/factors/pose_parametrization.hpp"
#include "navaid/simulation/imu_model.hpp"
#include "navaid/simulation/walker_trajectory.hpp"
#include "test_support.hpp"

namespace navaid::estimation {
namespace {

using testing::jacobians_match;

struct Keyframe {
  double pose[kPoseSize];
  double speed_bias[kSpeedBiasSize];
};

Keyframe keyframe(const SE3& T, const Vec3& v, const Vec3& bg, const Vec3& ba) {
  Keyframe k;
  pose_to_block(T, k.pose);
  Eigen::Map<Eigen::Matrix<double, 9, 1>> sb(k.speed_bias);
  sb << v, bg, ba;
  return k;
}

// Noiseless biased IMU stream of a walk, keyframes at off-grid times, true states.
struct Scenario {
  ImuPreintegration pre;
  Keyframe i, j;
};

Scenario walk_scenario(double t_i, double t_j) {
  const simulation::WalkerTrajectory traj({{0.0, 0.0}, {6.0, 0.0}, {6.0, 4.0}, {1.0, 7.0}});
  const Vec3 bg(0.01, -0.02, 0.015), ba(0.1, 0.05, -0.2);
  simulation::ImuModelOptions opt;
  opt.white_noise = false;
  opt.bias_walk = false;
  opt.initial_gyro_bias = bg;
  opt.initial_accel_bias = ba;
  simulation::ImuModel model(navaid::testing::euroc_imu_calibration(), opt);
  const auto stream = simulation::simulate_imu_stream(traj, model, t_i - 0.1, t_j + 0.1);
  // Linearized at a slightly wrong bias so that the first-order correction is exercised.
  ImuPreintegration pre = ImuPreintegration::between(stream.samples, seconds_to_ns(t_i), seconds_to_ns(t_j),
                                                     ImuNoise::from(navaid::testing::euroc_imu_calibration()), bg + Vec3(2e-4, -1e-4, 1e-4),
                                                     ba + Vec3(-2e-3, 1e-3, 2e-3));
  const auto si = traj.state(t_i), sj = traj.state(t_j);
  return {pre, keyframe(si.T_W_B, si.v_W, bg, ba), keyframe(sj.T_W_B, sj.v_W, bg, ba)};
}

Eigen::Matrix<double, 15, 1> residual(const ImuFactor& f, Keyframe& i, Keyframe& j) {
  std::vector<double*> blocks{i.pose, i.speed_bias, j.pose, j.speed_bias};
  Eigen::Matrix<double, 15, 1> r;
  EXPECT_TRUE(f.Evaluate(blocks.data(), r.data(), nullptr));
  return r;
}

TEST(ImuFactor, ResidualVanishesAtTheTrueStates) {
  Scenario s = walk_scenario(2.0037, 3.0037);
  const ImuFactor f(s.pre);
  const Eigen::Matrix<double, 15, 1> r = residual(f, s.i, s.j);
  // Whitened: the mid-point discretization at 200 Hz (O(h^2), ~1e-4 m over 1 s of walking) and
  // the second-order bias-correction remainder stay well below one standard deviation.
  EXPECT_LT(r.norm(), 0.3) << r.transpose();
  // Unwhitened (L r): rotation, position, velocity errors.
  const Eigen::Matrix<double, 15, 1> e = f.sqrt_information().triangularView<Eigen::Lower>().solve(r);
  EXPECT_LT(e.segment<3>(kTheta).norm(), 5e-6);
  EXPECT_LT(e.segment<3>(kAlpha).norm(), 2e-4);
  EXPECT_LT(e.segment<3>(kBeta).norm(), 1e-4) << e.transpose();
  EXPECT_LT(e.tail<6>().norm(), 1e-15);

  // A 1 cm position error at j is many sigmas.
  s.j.pose[0] += 0.01;
  EXPECT_GT(residual(f, s.i, s.j).norm(), 5.0);
}

TEST(ImuFactor, AnalyticJacobiansMatchNumericOnTheManifold) {
  std::mt19937_64 rng(3);
  const PoseManifold pose_manifold;
  for (int trial = 0; trial < 5; ++trial) {
    Scenario s = walk_scenario(1.0 + 0.7 * trial, 2.0 + 0.9 * trial);
    const ImuFactor f(s.pre);
    // Random, non-trivial states around the truth: every Jacobian block sees non-zero residuals.
    auto perturb = [&](Keyframe& k) {
      const SE3 T = se3_boxplus(pose_from_block(k.pose), [&] {
        Vec6 xi;
        xi << testing::random_vector(rng, 0.3), testing::random_vector(rng, 0.3);
        return xi;
      }());
      pose_to_block(T, k.pose);
      Eigen::Map<Eigen::Matrix<double, 9, 1>> sb(k.speed_bias);
      sb.head<3>() += testing::random_vector(rng, 0.2);
      sb.segment<3>(3) += testing::random_vector(rng, 0.02);
      sb.tail<3>() += testing::random_vector(rng, 0.2);
    };
    perturb(s.i);
    perturb(s.j);
    EXPECT_TRUE(jacobians_match(f, {s.i.pose, s.i.speed_bias, s.j.pose, s.j.speed_bias},
                                {&pose_manifold, nullptr, &pose_manifold, nullptr}))
        << "trial " << trial;
  }
}

TEST(ImuFactor, SolvesForTheSecondKeyframe) {
  Scenario s = walk_scenario(1.5, 2.5);
  const Keyframe truth = s.j;
  // Start 30 cm, 0.2 rad, 0.3 m/s and some bias away; keyframe i fixed.
  pose_to_block(se3_boxplus(pose_from_block(s.j.pose), (Vec6() << 0.2, -0.1, 0.2, 0.1, -0.15, 0.05).finished()),
                s.j.pose);
  s.j.speed_bias[0] += 0.3;
  s.j.speed_bias[4] += 0.01;
  s.j.speed_bias[8] -= 0.1;
  ceres::Problem problem;
  problem.AddResidualBlock(new ImuFactor(s.pre), nullptr, s.i.pose, s.i.speed_bias, s.j.pose, s.j.speed_bias);
  problem.SetManifold(s.i.pose, new PoseManifold);
  problem.SetManifold(s.j.pose, new PoseManifold);
  problem.SetParameterBlockConstant(s.i.pose);
  problem.SetParameterBlockConstant(s.i.speed_bias);
  ceres::Solver::Options options;
  options.max_num_iterations = 20;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  ASSERT_TRUE(summary.IsSolutionUsable()) << summary.BriefReport();
  EXPECT_TRUE(pose_from_block(s.j.pose).is_approx(pose_from_block(truth.pose), 1e-4)) << summary.BriefReport();
  for (int k = 0; k < kSpeedBiasSize; ++k) EXPECT_NEAR(s.j.speed_bias[k], truth.speed_bias[k], 2e-4) << k;
}

TEST(ImuFactor, RejectsDegeneratePreintegrations) {
  ImuPreintegration empty(ImuNoise::from(navaid::testing::euroc_imu_calibration()), Vec3::Zero(), Vec3::Zero());
  EXPECT_THROW(ImuFactor{empty}, Error);
  ImuPreintegration noiseless(ImuNoise{}, Vec3::Zero(), Vec3::Zero());
  for (int k = 0; k < 3; ++k) {
    ImuSample s;
    s.t = k * 5'000'000;
    noiseless.add(s);
  }
  EXPECT_THROW(ImuFactor{noiseless}, Error);
}

}  // namespace
}  // namespace navaid::estimation
