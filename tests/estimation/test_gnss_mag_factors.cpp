// GPS position factor (with and without a multipath bias), the Gauss-Markov link of the bias,
// and the magnetometer yaw factor.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <vector>

#include <ceres/ceres.h>

#include "factor_check.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/estimation/factors/gauss_markov_factor.hpp"
#include "navaid/estimation/factors/gps_position_factor.hpp"
#include "navaid/estimation/factors/magnetometer_yaw_factor.hpp"
#include "navaid/estimation/factors/pose_parametrization.hpp"
#include "navaid/simulation/magnetometer_model.hpp"

namespace navaid::estimation {
namespace {

using testing::jacobians_match;
using testing::random_pose;
using testing::random_vector;


TEST(GpsPositionFactor, KnownAnswer) {
  // yaw 90 deg maps W's x axis onto north; antenna 0.5 m above the body origin.
  double pose[kPoseSize], align[4] = {M_PI / 2, 1.0, 2.0, 3.0};
  pose_to_block(SE3(Quat::Identity(), Vec3(1.0, 0.0, 0.0)), pose);
  const Vec3 lever(0.0, 0.0, 0.5);
  const Mat3 cov = Vec3(4.0, 4.0, 9.0).asDiagonal();
  const GpsPositionFactor exact(Vec3(1.0, 3.0, 3.5), cov, lever);
  const double* p[] = {pose, align};
  Vec3 r;
  ASSERT_TRUE(exact.Evaluate(p, r.data(), nullptr));
  EXPECT_LT(r.norm(), 1e-12);
  const GpsPositionFactor off(Vec3(-1.0, 3.0, 0.5), cov, lever);  // 2 m west, 3 m low
  ASSERT_TRUE(off.Evaluate(p, r.data(), nullptr));
  EXPECT_LT((r - Vec3(1.0, 0.0, 1.0)).norm(), 1e-12);
}

TEST(GpsPositionFactor, AnalyticJacobiansMatchNumericOnTheManifold) {
  std::mt19937_64 rng(31);
  const PoseManifold pm;
  std::uniform_real_distribution<double> yaw(-M_PI, M_PI);
  for (int trial = 0; trial < 20; ++trial) {
    double pose[kPoseSize];
    pose_to_block(random_pose(rng, 20.0), pose);
    const Vec3 t = random_vector(rng, 50.0);
    double align[4] = {yaw(rng), t.x(), t.y(), t.z()};
    Mat3 A = Mat3::Random();
    const Mat3 cov = A * A.transpose() + Mat3::Identity();  // correlated, full
    const Vec3 lever = random_vector(rng, 0.5);  // drawn last argument first: the order of record (random_draws.hpp)
    const GpsPositionFactor f(random_vector(rng, 50.0), cov, lever);
    EXPECT_TRUE(jacobians_match(f, {pose, align}, {&pm, nullptr})) << "trial " << trial;
  }
}

TEST(GpsPositionBiasFactor, IsThePlainFactorShiftedByTheBias) {
  std::mt19937_64 rng(5);
  double pose[kPoseSize], align[4] = {0.3, 1.0, -2.0, 0.5};
  pose_to_block(random_pose(rng, 10.0), pose);
  const Vec3 z = random_vector(rng, 20.0), lever(0.1, 0.0, 0.3);
  const Mat3 cov = Vec3(4.0, 9.0, 16.0).asDiagonal();
  const GpsPositionFactor plain(z, cov, lever);
  const GpsPositionBiasFactor biased(z, cov, lever);
  double zero[3] = {0, 0, 0}, bias[3] = {1.0, -3.0, 2.0};
  Vec3 r0, r1, r2;
  const double* p0[] = {pose, align};
  const double* p1[] = {pose, align, zero};
  const double* p2[] = {pose, align, bias};
  ASSERT_TRUE(plain.Evaluate(p0, r0.data(), nullptr));
  ASSERT_TRUE(biased.Evaluate(p1, r1.data(), nullptr));
  ASSERT_TRUE(biased.Evaluate(p2, r2.data(), nullptr));
  EXPECT_LT((r1 - r0).norm(), 1e-12);
  // A bias of b moves the predicted fix by b: r changes by L^-1 b = (0.5, -1, 0.5) here.
  EXPECT_LT((r2 - r0 - Vec3(0.5, -1.0, 0.5)).norm(), 1e-12);
}

TEST(GpsPositionBiasFactor, AnalyticJacobiansMatchNumericOnTheManifold) {
  std::mt19937_64 rng(37);
  const PoseManifold pm;
  for (int trial = 0; trial < 10; ++trial) {
    double pose[kPoseSize];
    pose_to_block(random_pose(rng, 20.0), pose);
    const Vec3 t = random_vector(rng, 50.0), b = random_vector(rng, 3.0);
    double align[4] = {0.1 * trial - 0.4, t.x(), t.y(), t.z()}, bias[3] = {b.x(), b.y(), b.z()};
    Mat3 A = Mat3::Random();
    const Vec3 lever = random_vector(rng, 0.5);  // drawn last argument first: the order of record (random_draws.hpp)
    const GpsPositionBiasFactor f(random_vector(rng, 50.0), A * A.transpose() + Mat3::Identity(), lever);
    EXPECT_TRUE(jacobians_match(f, {pose, align, bias}, {&pm, nullptr, nullptr})) << "trial " << trial;
  }
}

TEST(GaussMarkovFactor, WhitensTheProcessStep) {
  // tau = dt / ln 2: phi = 0.5, step variance (1 - 0.25) Sigma.
  const Mat3 sigma = Vec3(4.0, 4.0, 16.0).asDiagonal();
  const GaussMarkovFactor f(1.0, 1.0 / std::log(2.0), sigma);
  EXPECT_NEAR(f.phi(), 0.5, 1e-15);
  double previous[3] = {2.0, -2.0, 4.0}, current[3] = {1.0, -1.0, 2.0 + std::sqrt(12.0)};
  const double* p[] = {previous, current};
  Vec3 r;
  ASSERT_TRUE(f.Evaluate(p, r.data(), nullptr));
  // current - phi previous = (0, 0, sqrt 12), whitened by sqrt(0.75 * 16) = sqrt 12.
  EXPECT_LT((r - Vec3(0.0, 0.0, 1.0)).norm(), 1e-12);
  std::mt19937_64 rng(3);
  Mat3 A = Mat3::Random();
  const GaussMarkovFactor g(0.7, 30.0, A * A.transpose() + Mat3::Identity());
  const Vec3 a = random_vector(rng, 2.0), c = random_vector(rng, 2.0);
  double x0[3] = {a.x(), a.y(), a.z()}, x1[3] = {c.x(), c.y(), c.z()};
  EXPECT_TRUE(jacobians_match(g, {x0, x1}, {nullptr, nullptr}));
}

TEST(GaussMarkovFactor, RejectsBadArguments) {
  EXPECT_THROW(GaussMarkovFactor(-1.0, 30.0, Mat3::Identity()), Error);
  EXPECT_THROW(GaussMarkovFactor(1.0, 0.0, Mat3::Identity()), Error);
  EXPECT_THROW(GaussMarkovFactor(0.0, 30.0, Mat3::Identity()), Error);  // no noise in a zero step
  EXPECT_THROW(GaussMarkovFactor(1.0, 30.0, -Mat3::Identity()), Error);
}

TEST(GpsPositionFactor, RejectsBadCovariance) {
  EXPECT_THROW(GpsPositionFactor(Vec3::Zero(), Mat3::Zero(), Vec3::Zero()), Error);
  Mat3 asym = Mat3::Identity();
  asym(0, 1) = 0.5;
  EXPECT_THROW(GpsPositionFactor(Vec3::Zero(), asym, Vec3::Zero()), Error);
  EXPECT_THROW(GpsPositionFactor(Vec3(NAN, 0, 0), Mat3::Identity(), Vec3::Zero()), Error);
}

TEST(MagnetometerYawFactor, ZeroAtTruthWithTheSimulatedFieldAndYawKnownAnswer) {
  simulation::MagnetometerModelConfig cfg;
  cfg.noise = false;
  cfg.field_enu_t = Vec3(2e-6, 20e-6, -45e-6);  // a little declination
  const simulation::MagnetometerModel model(cfg);
  const double sigma = magnetometer_yaw_sigma(0.2e-6, cfg.field_enu_t);
  EXPECT_NEAR(sigma, 0.2e-6 / std::hypot(2e-6, 20e-6), 1e-15);
  std::mt19937_64 rng(41);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI);
  for (int trial = 0; trial < 20; ++trial) {
    const double yaw_ew = angle(rng), body_yaw = angle(rng);
    const SE3 T_ENU_W(quat_from_rpy(0.0, 0.0, yaw_ew), random_vector(rng, 10.0));
    // Drawn last argument first: the order of record (random_draws.hpp).
    const Vec3 t_W_B = random_vector(rng, 10.0);
    const double pitch = 0.2 * angle(rng);
    const SE3 T_W_B(quat_from_rpy(0.3 * angle(rng), pitch, body_yaw), t_W_B);
    const MagnetometerYawFactor f(model.expected_field_B(T_ENU_W, T_W_B), cfg.field_enu_t, sigma);
    double pose[kPoseSize], align[4] = {yaw_ew, T_ENU_W.t.x(), T_ENU_W.t.y(), T_ENU_W.t.z()};
    pose_to_block(T_W_B, pose);
    const double* p[] = {pose, align};
    double r;
    ASSERT_TRUE(f.Evaluate(p, &r, nullptr));
    EXPECT_NEAR(r, 0.0, 1e-9);
    // Turning the alignment by 0.02 rad turns the predicted heading by the same angle.
    align[0] += 0.02;
    ASSERT_TRUE(f.Evaluate(p, &r, nullptr));
    EXPECT_NEAR(r * sigma, 0.02, 1e-12);
  }
  // Level body: the heading residual is the body yaw error, wrapped to (-pi, pi].
  const SE3 T_ENU_W = SE3::identity();
  const SE3 T_W_B(quat_from_rpy(0.0, 0.0, 3.0), Vec3::Zero());
  const MagnetometerYawFactor f(model.expected_field_B(T_ENU_W, T_W_B), cfg.field_enu_t, sigma);
  double pose[kPoseSize], align[4] = {0.0, 0.0, 0.0, 0.0};
  pose_to_block(SE3(quat_from_rpy(0.0, 0.0, -3.0), Vec3::Zero()), pose);
  const double* p[] = {pose, align};
  double r;
  ASSERT_TRUE(f.Evaluate(p, &r, nullptr));
  EXPECT_NEAR(r * sigma, 2.0 * M_PI - 6.0, 1e-12);
}

TEST(MagnetometerYawFactor, AnalyticJacobiansMatchNumericOnTheManifold) {
  std::mt19937_64 rng(42);
  const PoseManifold pm;
  std::uniform_real_distribution<double> yaw(-M_PI, M_PI);
  for (int trial = 0; trial < 20; ++trial) {
    double pose[kPoseSize];
    pose_to_block(random_pose(rng), pose);
    double align[4] = {yaw(rng), 1.0, 2.0, 3.0};
    const Vec3 field_B = random_vector(rng, 50e-6);
    const MagnetometerYawFactor f(field_B, Vec3(0.0, 20e-6, -45e-6), 0.02);
    double r;
    const double* p[] = {pose, align};
    ASSERT_TRUE(f.Evaluate(p, &r, nullptr));
    if (std::abs(std::abs(r * 0.02) - M_PI) < 1e-3) continue;  // the wrap is not differentiable
    EXPECT_TRUE(jacobians_match(f, {pose, align}, {&pm, nullptr})) << "trial " << trial;
  }
}

TEST(MagnetometerYawFactor, RejectsFieldsWithoutHeading) {
  EXPECT_THROW(MagnetometerYawFactor(Vec3::Zero(), Vec3(0, 20e-6, -45e-6), 0.01), Error);
  EXPECT_THROW(MagnetometerYawFactor(Vec3(1e-5, 0, 0), Vec3(0, 0, -45e-6), 0.01), ConfigError);  // at a pole
  EXPECT_THROW(MagnetometerYawFactor(Vec3(1e-5, 0, 0), Vec3(0, 20e-6, -45e-6), 0.0), ConfigError);
  EXPECT_THROW(magnetometer_yaw_sigma(0.0, Vec3(0, 20e-6, 0)), ConfigError);
}

TEST(GpsAndMagnetometerFactors, SolveTheEnuAlignmentOfAKnownTrack) {
  // Known body poses along a walk; noise-free fixes (with lever arm) and field samples. Starting
  // 0.8 rad and 20 m off, the 4-DOF alignment converges to the truth.
  std::mt19937_64 rng(51);
  const SE3 T_ENU_W(quat_from_rpy(0.0, 0.0, 1.1), Vec3(12.0, -7.0, 0.5));
  const Vec3 lever(0.1, 0.0, 0.3), field_enu(1e-6, 20e-6, -45e-6);
  simulation::MagnetometerModelConfig cfg;
  cfg.noise = false;
  cfg.field_enu_t = field_enu;
  const simulation::MagnetometerModel model(cfg);
  std::vector<std::array<double, kPoseSize>> poses(12);
  double align[4] = {1.1 - 0.8, 0.0, 5.0, -3.0};
  ceres::Problem problem;
  for (int k = 0; k < 12; ++k) {
    const SE3 T_W_B(quat_from_rpy(0.05, -0.03, 0.4 * k), Vec3(1.2 * k, 0.3 * k * k / 10.0, 1.7));
    pose_to_block(T_W_B, poses[k].data());
    const Vec3 fix = T_ENU_W * (T_W_B * lever);
    problem.AddResidualBlock(new GpsPositionFactor(fix, Vec3(4.0, 4.0, 9.0).asDiagonal(), lever), nullptr,
                             poses[k].data(), align);
    problem.AddResidualBlock(new MagnetometerYawFactor(model.expected_field_B(T_ENU_W, T_W_B), field_enu, 0.05),
                             nullptr, poses[k].data(), align);
    problem.SetManifold(poses[k].data(), new PoseManifold);
    problem.SetParameterBlockConstant(poses[k].data());
  }
  ceres::Solver::Options options;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  ASSERT_TRUE(summary.IsSolutionUsable()) << summary.BriefReport();
  EXPECT_NEAR(align[0], 1.1, 1e-8);
  EXPECT_LT((Vec3(align[1], align[2], align[3]) - T_ENU_W.t).norm(), 1e-7);
  EXPECT_LT(summary.final_cost, 1e-12);
}

}  // namespace
}  // namespace navaid::estimation
