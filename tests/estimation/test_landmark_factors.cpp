// Factors on a 3-DOF anchored landmark [x_a, y_a, lambda] (anchor bearing estimated).
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "factor_check.hpp"
#include "two_view_scene.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/estimation/factors/inverse_depth_factor.hpp"
#include "navaid/estimation/factors/landmark_factors.hpp"
#include "navaid/estimation/factors/pose_parametrization.hpp"

namespace navaid::estimation {
namespace {

using testing::jacobians_match;

constexpr double kFocal = 460.0;
constexpr double kSigmaPx = 1.0;

// The landmark block [x_a, y_a, lambda] of the shared two-view scene.
using Scene = testing::TwoViews;
Scene scene(std::mt19937_64& rng) { return testing::two_views(rng); }
void perturb_with_bearing(Scene& s, std::mt19937_64& rng) { testing::perturb(s, rng, true); }

std::vector<double*> visual_blocks(Scene& s) { return {s.anchor, s.target, s.extrinsic, s.landmark}; }

TEST(LandmarkFactors, ZeroAtTruth) {
  std::mt19937_64 rng(31);
  const double sigma_lambda = inverse_depth_sigma(0.1, kFocal, 0.065);
  for (int trial = 0; trial < 10; ++trial) {
    Scene s = scene(rng);
    const double* anchor_block[] = {s.landmark};
    Eigen::Vector3d r3;
    Eigen::Vector2d r2;
    double r1;
    ASSERT_TRUE(AnchorBearingFactor(s.m_anchor, kFocal, kSigmaPx).Evaluate(anchor_block, r2.data(), nullptr));
    EXPECT_LT(r2.norm(), 1e-12);
    ASSERT_TRUE(AnchorInverseDepthFactor(s.z_anchor, sigma_lambda).Evaluate(anchor_block, &r1, nullptr));
    EXPECT_LT(std::abs(r1), 1e-9);
    ASSERT_TRUE(LandmarkReprojectionFactor(s.m_target, kFocal, kSigmaPx).Evaluate(visual_blocks(s).data(), r2.data(),
                                                                                nullptr));
    EXPECT_LT(r2.norm(), 1e-8);
    ASSERT_TRUE(LandmarkDepth3dFactor(s.m_target, s.z_target, kFocal, sigma_lambda, kSigmaPx)
                    .Evaluate(visual_blocks(s).data(), r3.data(), nullptr));
    EXPECT_LT(r3.norm(), 1e-8);
  }
}

// With the bearing block equal to the anchor measurement, the landmark factors are the plain
// factors (whose bearing is that measurement), residual for residual.
TEST(LandmarkFactors, EqualThePlainFactorsAtTheMeasuredBearing) {
  std::mt19937_64 rng(32);
  const double sigma_lambda = inverse_depth_sigma(0.1, kFocal, 0.065);
  for (int trial = 0; trial < 10; ++trial) {
    Scene s = scene(rng);
    perturb_with_bearing(s, rng);
    const Eigen::Vector2d bearing(s.landmark[0], s.landmark[1]);
    const double* plain[] = {s.anchor, s.target, s.extrinsic, &s.landmark[2]};
    Eigen::Vector2d a2, b2;
    ASSERT_TRUE(LandmarkReprojectionFactor(s.m_target, kFocal, kSigmaPx).Evaluate(visual_blocks(s).data(), a2.data(),
                                                                                nullptr));
    ASSERT_TRUE(ReprojectionFactor(bearing, s.m_target, kFocal, kSigmaPx).Evaluate(plain, b2.data(), nullptr));
    EXPECT_LT((a2 - b2).norm(), 1e-12);
    Eigen::Vector3d a3, b3;
    ASSERT_TRUE(LandmarkDepth3dFactor(s.m_target, s.z_target, kFocal, sigma_lambda, kSigmaPx)
                    .Evaluate(visual_blocks(s).data(), a3.data(), nullptr));
    ASSERT_TRUE(Depth3dFactor(bearing, s.m_target, s.z_target, kFocal, sigma_lambda, kSigmaPx)
                    .Evaluate(plain, b3.data(), nullptr));
    EXPECT_LT((a3 - b3).norm(), 1e-12);
    // The anchor bearing's residual is the pixel offset in sigmas.
    const double* anchor_block[] = {s.landmark};
    ASSERT_TRUE(AnchorBearingFactor(s.m_anchor, kFocal, kSigmaPx).Evaluate(anchor_block, a2.data(), nullptr));
    EXPECT_NEAR(a2.x(), 0.01 * kFocal / kSigmaPx, 1e-9);
    EXPECT_NEAR(a2.y(), -0.02 * kFocal / kSigmaPx, 1e-9);
  }
}

TEST(LandmarkFactors, AnalyticJacobiansMatchNumericOnTheManifold) {
  std::mt19937_64 rng(33);
  const PoseManifold pm;
  const double sigma_lambda = inverse_depth_sigma(0.1, kFocal, 0.065);
  for (int trial = 0; trial < 20; ++trial) {
    Scene s = scene(rng);
    const Scene measured = s;
    perturb_with_bearing(s, rng);
    const std::vector<const ceres::Manifold*> manifolds{&pm, &pm, &pm, nullptr};
    EXPECT_TRUE(jacobians_match(LandmarkReprojectionFactor(measured.m_target, kFocal, kSigmaPx), visual_blocks(s),
                                manifolds))
        << "trial " << trial;
    for (const auto model : {Depth3dCovariance::kFull, Depth3dCovariance::kPaper}) {
      EXPECT_TRUE(jacobians_match(
          LandmarkDepth3dFactor(measured.m_target, measured.z_target, kFocal, sigma_lambda, kSigmaPx, model),
          visual_blocks(s), manifolds))
          << "trial " << trial;
    }
    EXPECT_TRUE(jacobians_match(AnchorBearingFactor(measured.m_anchor, kFocal, kSigmaPx), {s.landmark}, {nullptr}));
    EXPECT_TRUE(
        jacobians_match(AnchorInverseDepthFactor(measured.z_anchor, sigma_lambda), {s.landmark}, {nullptr}));
  }
}

// Time-offset versions: at td = td0 the plain landmark factors; Jacobians (td included) numeric.
TEST(LandmarkFactors, TimeOffsetVersionsMatchAtTd0AndTheirJacobiansMatchNumeric) {
  std::mt19937_64 rng(34);
  const PoseManifold pm;
  const double sigma_lambda = inverse_depth_sigma(0.1, kFocal, 0.065);
  for (int trial = 0; trial < 10; ++trial) {
    Scene s = scene(rng);
    const Scene measured = s;
    perturb_with_bearing(s, rng);
    const TimedObservation anchor{measured.m_anchor, Eigen::Vector2d(0.3, -0.2), 0.004};
    const TimedObservation target{measured.m_target, Eigen::Vector2d(-0.5, 0.1), 0.006};
    const LandmarkReprojectionTdFactor reprojection(target, kFocal, kSigmaPx);
    const LandmarkDepth3dTdFactor depth(target, measured.z_target, 0.4, kFocal, sigma_lambda, kSigmaPx);
    const AnchorBearingTdFactor bearing(anchor, kFocal, kSigmaPx);
    double td[1] = {target.td0_s};
    std::vector<double*> blocks = visual_blocks(s);
    blocks.push_back(td);
    Eigen::Vector2d a2, b2;
    ASSERT_TRUE(reprojection.Evaluate(blocks.data(), a2.data(), nullptr));
    ASSERT_TRUE(LandmarkReprojectionFactor(measured.m_target, kFocal, kSigmaPx)
                    .Evaluate(visual_blocks(s).data(), b2.data(), nullptr));
    EXPECT_EQ(a2, b2);
    Eigen::Vector3d a3, b3;
    ASSERT_TRUE(depth.Evaluate(blocks.data(), a3.data(), nullptr));
    ASSERT_TRUE(LandmarkDepth3dFactor(measured.m_target, measured.z_target, kFocal, sigma_lambda, kSigmaPx)
                    .Evaluate(visual_blocks(s).data(), b3.data(), nullptr));
    EXPECT_EQ(a3, b3);
    td[0] = 0.015;
    const std::vector<const ceres::Manifold*> manifolds{&pm, &pm, &pm, nullptr, nullptr};
    EXPECT_TRUE(jacobians_match(reprojection, blocks, manifolds)) << "trial " << trial;
    EXPECT_TRUE(jacobians_match(depth, blocks, manifolds)) << "trial " << trial;
    EXPECT_TRUE(jacobians_match(bearing, {s.landmark, td}, {nullptr, nullptr})) << "trial " << trial;
  }
}

TEST(LandmarkFactors, RejectBadInput) {
  EXPECT_THROW(AnchorBearingFactor(Eigen::Vector2d(std::nan(""), 0.0), kFocal, 1.0), Error);
  EXPECT_THROW(AnchorBearingFactor(Eigen::Vector2d::Zero(), 0.0, 1.0), ConfigError);
  EXPECT_THROW(AnchorBearingFactor(Eigen::Vector2d::Zero(), kFocal, -1.0), ConfigError);
  EXPECT_THROW(AnchorInverseDepthFactor(0.0, 0.01), Error);
  EXPECT_THROW(AnchorInverseDepthFactor(2.0, 0.0), ConfigError);
  EXPECT_THROW(LandmarkReprojectionFactor(Eigen::Vector2d::Zero(), kFocal, 0.0), ConfigError);
  EXPECT_THROW(LandmarkDepth3dFactor(Eigen::Vector2d::Zero(), -1.0, kFocal, 0.01, 1.0), Error);
  const TimedObservation bad{Eigen::Vector2d::Zero(), Eigen::Vector2d(std::nan(""), 0.0), 0.0};
  EXPECT_THROW(AnchorBearingTdFactor(bad, kFocal, 1.0), Error);
  EXPECT_THROW(LandmarkReprojectionTdFactor(bad, kFocal, 1.0), Error);
  EXPECT_THROW(LandmarkDepth3dTdFactor(TimedObservation{}, 2.0, std::nan(""), kFocal, 0.01, 1.0), Error);
}

}  // namespace
}  // namespace navaid::estimation
