// Reprojection, inverse-depth and depth-augmented 3D factors.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "factor_check.hpp"
#include "two_view_scene.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/core/random_draws.hpp"
#include "navaid/estimation/factors/depth_3d_factor.hpp"
#include "navaid/estimation/factors/inverse_depth_factor.hpp"
#include "navaid/estimation/factors/pose_parametrization.hpp"
#include "navaid/estimation/factors/reprojection_factor.hpp"

namespace navaid::estimation {
namespace {

using testing::jacobians_match;
using testing::random_pose;
using testing::random_rotation;
using testing::random_vector;

using testing::TwoViews;
using testing::two_views;
using testing::perturb;

// The feature in the target camera for the (possibly perturbed) blocks of v.
Vec3 point_in_target(const TwoViews& v) {
  const Vec3 P_ca = Vec3(v.m_anchor.x(), v.m_anchor.y(), 1.0) / *v.lambda();
  const SE3 T_B_C = pose_from_block(v.extrinsic);
  return (T_B_C.inverse() * pose_from_block(v.target).inverse() * pose_from_block(v.anchor) * T_B_C) * P_ca;
}

std::vector<double*> blocks(TwoViews& v) { return {v.anchor, v.target, v.extrinsic, v.lambda()}; }

constexpr double kVisualFocal = 525.0;

TEST(ReprojectionFactor, ZeroAtTruthAndPixelScaledOffIt) {
  std::mt19937_64 rng(11);
  for (int trial = 0; trial < 20; ++trial) {
    TwoViews v = two_views(rng);
    const ReprojectionFactor f(v.m_anchor, v.m_target, kVisualFocal, 1.5);
    Eigen::Vector2d r;
    ASSERT_TRUE(f.Evaluate(blocks(v).data(), r.data(), nullptr));
    EXPECT_LT(r.norm(), 1e-9);
    perturb(v, rng);
    const Vec3 P = point_in_target(v);
    ASSERT_TRUE(f.Evaluate(blocks(v).data(), r.data(), nullptr));
    const Eigen::Vector2d expected = kVisualFocal / 1.5 * (P.head<2>() / P.z() - v.m_target);
    EXPECT_LT((r - expected).norm(), 1e-9 * (1.0 + expected.norm()));
  }
}

TEST(ReprojectionFactor, AnalyticJacobiansMatchNumericOnTheManifold) {
  std::mt19937_64 rng(12);
  const PoseManifold pm;
  for (int trial = 0; trial < 20; ++trial) {
    TwoViews v = two_views(rng);
    const ReprojectionFactor f(v.m_anchor, v.m_target, kVisualFocal, 1.5);
    perturb(v, rng);
    EXPECT_TRUE(jacobians_match(f, blocks(v), {&pm, &pm, &pm, nullptr})) << "trial " << trial;
  }
}

TEST(ReprojectionFactor, RejectsBadSettingsAndPointsBehindTheCamera) {
  EXPECT_THROW(ReprojectionFactor({0, 0}, {0, 0}, 0.0, 1.0), ConfigError);
  EXPECT_THROW(ReprojectionFactor({0, 0}, {0, 0}, 500.0, -1.0), ConfigError);
  std::mt19937_64 rng(13);
  TwoViews v = two_views(rng);
  const ReprojectionFactor f(v.m_anchor, v.m_target, kVisualFocal, 1.5);
  *v.lambda() = -*v.lambda();  // the point is now behind both cameras
  Eigen::Vector2d r;
  EXPECT_FALSE(f.Evaluate(blocks(v).data(), r.data(), nullptr));
}

TEST(InverseDepthFactor, KnownAnswersAndJacobian) {
  // Disparity d = f b / Z: sigma_d = 0.2 px, f = 500 px, b = 0.08 m -> sigma_lambda = 0.005 1/m.
  const double sigma = inverse_depth_sigma(0.2, 500.0, 0.08);
  EXPECT_DOUBLE_EQ(sigma, 0.005);
  const InverseDepthFactor f(2.0, sigma);
  double lambda[1] = {0.5};
  double r;
  const double* p[] = {lambda};
  ASSERT_TRUE(f.Evaluate(p, &r, nullptr));
  EXPECT_DOUBLE_EQ(r, 0.0);
  lambda[0] = 0.49;  // e = 1/Z - lambda = 0.01 -> 2 sigma
  ASSERT_TRUE(f.Evaluate(p, &r, nullptr));
  EXPECT_NEAR(r, 2.0, 1e-12);
  EXPECT_TRUE(jacobians_match(f, {lambda}, {nullptr}));
  EXPECT_THROW(InverseDepthFactor(0.0, sigma), Error);
  EXPECT_THROW(InverseDepthFactor(2.0, 0.0), ConfigError);
  EXPECT_THROW(inverse_depth_sigma(0.2, 500.0, 0.0), ConfigError);
}

TEST(Depth3dFactor, ZeroAtTruthAndPaperResidualOffIt) {
  std::mt19937_64 rng(21);
  const double sigma_lambda = inverse_depth_sigma(0.2, kVisualFocal, 0.075);
  for (int trial = 0; trial < 20; ++trial) {
    TwoViews v = two_views(rng);
    const Depth3dFactor f(v.m_anchor, v.m_target, v.z_target, kVisualFocal, sigma_lambda, 1.5, Depth3dCovariance::kPaper);
    Vec3 r;
    ASSERT_TRUE(f.Evaluate(blocks(v).data(), r.data(), nullptr));
    EXPECT_LT(r.norm(), 1e-8);
    perturb(v, rng);
    ASSERT_TRUE(f.Evaluate(blocks(v).data(), r.data(), nullptr));
    // r = Sigma^-1/2 [X - X^, Y - Y^, 1/Z - 1/Z^], sigma_x = sigma_y = Z 1.5 / f.
    const Vec3 P = point_in_target(v);
    const double sxy = v.z_target * 1.5 / kVisualFocal;
    const Vec3 expected((v.m_target.x() * v.z_target - P.x()) / sxy, (v.m_target.y() * v.z_target - P.y()) / sxy,
                        (1.0 / v.z_target - 1.0 / P.z()) / sigma_lambda);
    EXPECT_LT((r - expected).norm(), 1e-9 * (1.0 + expected.norm()));
  }
}

TEST(Depth3dFactor, FullCovarianceResidualOffTruth) {
  std::mt19937_64 rng(23);
  const double sigma_lambda = inverse_depth_sigma(0.2, kVisualFocal, 0.075);
  for (int trial = 0; trial < 20; ++trial) {
    TwoViews v = two_views(rng);
    const Depth3dFactor f(v.m_anchor, v.m_target, v.z_target, kVisualFocal, sigma_lambda);  // kFull by default
    perturb(v, rng);
    Vec3 r;
    ASSERT_TRUE(f.Evaluate(blocks(v).data(), r.data(), nullptr));
    // The error of (x, y, 1/Z) that maps to the point error: x = X / Z^ ... to first order
    // [dX / Z + x Z d(1/Z), dY / Z + y Z d(1/Z), d(1/Z)], whitened by sigma / f and sigma_lambda.
    const Vec3 P = point_in_target(v);
    const double Z = v.z_target, x = v.m_target.x(), y = v.m_target.y(), sn = 1.5 / kVisualFocal;
    const Vec3 d(x * Z - P.x(), y * Z - P.y(), 1.0 / Z - 1.0 / P.z());
    const Vec3 expected((d.x() / Z + x * Z * d.z()) / sn, (d.y() / Z + y * Z * d.z()) / sn, d.z() / sigma_lambda);
    EXPECT_LT((r - expected).norm(), 1e-9 * (1.0 + expected.norm()));
  }
}

// Measurements drawn as the simulator draws them (pixel noise on u, v; white disparity noise, so
// Z = f b / (f b / Z_true + sigma_d n)) at a fixed true point near the image border, 3 m away:
// the full model whitens the point error to unit covariance, the paper's leaves the X variance
// several times too large and the X / (1/Z) terms correlated.
TEST(Depth3dFactor, FullCovarianceWhitensSimulatedDepthNoise) {
  const double f_px = 460.0, b = 0.065, sigma_d = 0.1, sigma_px = 1.0;
  const double sigma_lambda = inverse_depth_sigma(sigma_d, f_px, b);
  const Vec3 P_true(0.6 * 3.0, -0.4 * 3.0, 3.0);
  std::mt19937_64 rng(24);
  std::normal_distribution<double> n(0.0, 1.0);
  // The prediction is the true point: the anchor is the target, lambda the true inverse depth.
  double identity[kPoseSize], extrinsic[kPoseSize], lambda[1] = {1.0 / P_true.z()};
  pose_to_block(SE3(), identity);
  pose_to_block(SE3(), extrinsic);
  const double* p[] = {identity, identity, extrinsic, lambda};
  const Eigen::Vector2d m_true = P_true.head<2>() / P_true.z();
  for (const auto model : {Depth3dCovariance::kFull, Depth3dCovariance::kPaper}) {
    Mat3 second_moment = Mat3::Zero();
    const int draws = 20000;
    for (int i = 0; i < draws; ++i) {
      const Eigen::Vector2d m = m_true + sigma_px / f_px * draw_vector<2>([&] { return n(rng); });
      const double Z = f_px * b / (f_px * b / P_true.z() + sigma_d * n(rng));
      const Depth3dFactor factor(m_true, m, Z, f_px, sigma_lambda, sigma_px, model);
      Vec3 r;
      ASSERT_TRUE(factor.Evaluate(p, r.data(), nullptr));
      second_moment += r * r.transpose() / draws;
    }
    if (model == Depth3dCovariance::kFull) {
      EXPECT_LT((second_moment - Mat3::Identity()).cwiseAbs().maxCoeff(), 0.06) << second_moment;
    } else {
      EXPECT_GT(second_moment(0, 0), 4.0) << second_moment;
      EXPECT_GT(std::abs(second_moment(0, 2)), 0.5) << second_moment;
    }
  }
}

TEST(Depth3dFactor, AnalyticJacobiansMatchNumericOnTheManifold) {
  std::mt19937_64 rng(22);
  const PoseManifold pm;
  const double sigma_lambda = inverse_depth_sigma(0.2, kVisualFocal, 0.075);
  for (int trial = 0; trial < 20; ++trial) {
    TwoViews v = two_views(rng);
    const TwoViews measured = v;
    perturb(v, rng);
    for (const auto model : {Depth3dCovariance::kFull, Depth3dCovariance::kPaper}) {
      const Depth3dFactor f(measured.m_anchor, measured.m_target, measured.z_target, kVisualFocal, sigma_lambda, 1.5, model);
      EXPECT_TRUE(jacobians_match(f, blocks(v), {&pm, &pm, &pm, nullptr})) << "trial " << trial;
    }
  }
}

TEST(Depth3dFactor, RejectsBadInput) {
  EXPECT_THROW(Depth3dFactor({0, 0}, {0, 0}, 0.0, kVisualFocal, 0.01), Error);
  EXPECT_THROW(Depth3dFactor({0, 0}, {0, 0}, 2.0, kVisualFocal, 0.0), ConfigError);
  EXPECT_THROW(Depth3dFactor({0, 0}, {0, 0}, 2.0, -1.0, 0.01), ConfigError);
}

}  // namespace
}  // namespace navaid::estimation
