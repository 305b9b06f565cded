// Pose-change estimation (W-ROMA §V-A, eq. 1-3): HPnP and the 3D-2D PnP baseline on synthetic
// two-view scenes with a known T_j_i.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "navaid/core/errors.hpp"
#include "navaid/estimation/initialization/pose_change.hpp"
#include "navaid/estimation/initialization/pose_change_scene.hpp"
#include "test_support.hpp"

namespace navaid::estimation {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

// A walking step seen by a head-mounted camera: 0.3 m mostly forward, a few degrees of turn.
SE3 step_pose() { return SE3(quat_from_rpy(2.0 * kDeg, -3.0 * kDeg, 6.0 * kDeg), Vec3(0.08, -0.03, -0.29)); }

double rotation_error_deg(const SE3& a, const SE3& b) { return a.q.angularDistance(b.q) / kDeg; }
double translation_error_m(const SE3& a, const SE3& b) { return (a.t - b.t).norm(); }

PoseChange expect_pose(const TwoViewScene& s, PoseChangeMethod m, const PoseChangeOptions& o = {}) {
  std::string why;
  const auto p = estimate_pose_change(s.correspondences, m, o, &why);
  EXPECT_TRUE(p.has_value()) << to_string(m) << ": " << why;
  return p.value_or(PoseChange{});
}

TEST(PoseChange, BothMethodsRecoverThePoseWithPlentyOfDepth) {
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    TwoViewSceneOptions so;
    so.seed = seed;
    so.depth_noise_rel = 0.005;
    const TwoViewScene s = make_two_view_scene(step_pose(), so);
    for (auto m : {PoseChangeMethod::kHybrid, PoseChangeMethod::kPnp}) {
      const PoseChange p = expect_pose(s, m);
      // 0.5 px noise on 150 points, depth 0.5 %: errors are ~0.02 deg and ~3 mm; bounds 5-10x.
      EXPECT_LT(rotation_error_deg(p.T_j_i, s.T_j_i), 0.15) << to_string(m) << " seed " << seed;
      EXPECT_LT(translation_error_m(p.T_j_i, s.T_j_i), 0.02) << to_string(m) << " seed " << seed;
      EXPECT_GE(p.depth_inliers, 120) << to_string(m);
      EXPECT_FALSE(p.rotation_only);
    }
  }
}

TEST(PoseChange, ExactDataGivesTheExactPose) {
  TwoViewSceneOptions so;
  so.pixel_noise_px = 0.0;
  so.depth_features = 10;
  const TwoViewScene s = make_two_view_scene(step_pose(), so);
  for (auto m : {PoseChangeMethod::kHybrid, PoseChangeMethod::kPnp}) {
    const PoseChange p = expect_pose(s, m);
    EXPECT_LT(rotation_error_deg(p.T_j_i, s.T_j_i), 1e-6) << to_string(m);
    EXPECT_LT(translation_error_m(p.T_j_i, s.T_j_i), 1e-6) << to_string(m);
    EXPECT_EQ(p.depth_inliers, 10) << to_string(m);
  }
}

TEST(PoseChange, WithTwoOrThreeDepthFeaturesHpnpSucceedsAndPnpFails) {
  constexpr int kScenes = 30;
  for (int depth_features : {2, 3}) {
    int successes = 0;
    for (int seed = 1; seed <= kScenes; ++seed) {
      TwoViewSceneOptions so;
      so.seed = static_cast<std::uint64_t>(seed);
      so.depth_features = depth_features;
      so.min_depth_m = 2.0;
      so.depth_noise_rel = 0.002;
      const TwoViewScene s = make_two_view_scene(step_pose(), so);
      std::string why;
      const auto p = estimate_pose_change(s.correspondences, PoseChangeMethod::kHybrid, {}, &why);
      if (p) {
        // The rotation comes from all 150 features, whatever the depths.
        EXPECT_LT(rotation_error_deg(p->T_j_i, s.T_j_i), 0.15) << "seed " << seed;
        // The study's success bound (10 % of the 0.3 m step + 2 cm): two or three points at 2-8 m
        // fix the forward component poorly when they lie close together, so not every scene.
        successes += translation_error_m(p->T_j_i, s.T_j_i) < 0.1 * s.T_j_i.t.norm() + 0.02;
      }
      EXPECT_FALSE(estimate_pose_change(s.correspondences, PoseChangeMethod::kPnp, {}, &why).has_value());
      EXPECT_NE(why.find("too few features with depth"), std::string::npos) << why;
    }
    // ~95 % succeed (96 of 100 scenes with 2 depths): 30 scenes give 28.5 +- 1.2, 25 is ~3 sigma below.
    EXPECT_GE(successes, 25) << depth_features << " depth features";
  }
}

TEST(PoseChange, HpnpRejectsWhenFewerThanTwoDepthFeatures) {
  TwoViewSceneOptions so;
  so.depth_features = 1;
  const TwoViewScene s = make_two_view_scene(step_pose(), so);
  std::string why;
  EXPECT_FALSE(estimate_pose_change(s.correspondences, PoseChangeMethod::kHybrid, {}, &why).has_value());
  EXPECT_NE(why.find("depth"), std::string::npos) << why;
  PoseChangeOptions o;
  o.min_depth_inliers = 20;  // a stricter caller
  so.depth_features = 10;
  EXPECT_FALSE(estimate_pose_change(make_two_view_scene(step_pose(), so).correspondences, PoseChangeMethod::kHybrid, o)
                   .has_value());
}

TEST(PoseChange, TwentyPercentOutliersAreRejected) {
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    TwoViewSceneOptions so;
    so.seed = seed;
    so.outlier_fraction = 0.2;
    so.depth_features = 60;
    const TwoViewScene s = make_two_view_scene(step_pose(), so);
    for (auto m : {PoseChangeMethod::kHybrid, PoseChangeMethod::kPnp}) {
      const PoseChange p = expect_pose(s, m);
      EXPECT_LT(rotation_error_deg(p.T_j_i, s.T_j_i), 0.2) << to_string(m) << " seed " << seed;
      EXPECT_LT(translation_error_m(p.T_j_i, s.T_j_i), 0.03) << to_string(m) << " seed " << seed;
      // Outliers are >= 20 px off; one can still land near its epipolar line (HPnP's no-depth
      // features are only checked against it), so allow a few.
      int accepted_outliers = 0, rejected_depth_inliers = 0;
      for (std::size_t k = 0; k < s.outlier.size(); ++k) {
        if (s.outlier[k] && p.inlier[k]) ++accepted_outliers;
        if (!s.outlier[k] && s.correspondences[k].depth_i && !p.depth_inlier[k]) ++rejected_depth_inliers;
        if (s.outlier[k] && s.correspondences[k].depth_i) {
          EXPECT_FALSE(p.depth_inlier[k]) << to_string(m) << " " << k;
        }
      }
      EXPECT_LE(accepted_outliers, 3) << to_string(m) << " seed " << seed;
      // 1 px threshold on 0.5 px noise per coordinate in two frames: ~13 % of good points fall
      // outside (chi-square, 2 dof, sigma 0.71 px); 48 good depth points -> expect ~6, allow 15.
      EXPECT_LE(rejected_depth_inliers, 15) << to_string(m) << " seed " << seed;
    }
  }
}

TEST(PoseChange, WrongDepthsAreRejectedByHpnp) {
  TwoViewSceneOptions so;
  so.depth_features = 10;
  so.pixel_noise_px = 0.2;
  TwoViewScene s = make_two_view_scene(step_pose(), so);
  // Two depths 40 % off: the epipolar test cannot see them, the translation RANSAC must.
  *s.correspondences[1].depth_i *= 1.4;
  *s.correspondences[6].depth_i *= 0.6;
  for (bool reprojection : {false, true}) {
    PoseChangeOptions o;
    o.reprojection_translation = reprojection;
    const PoseChange p = expect_pose(s, PoseChangeMethod::kHybrid, o);
    EXPECT_FALSE(p.depth_inlier[1]);
    EXPECT_FALSE(p.depth_inlier[6]);
    // Eq. 3 as printed weighs each feature by its depth in j, so the nearest good feature may end
    // just over 1 px; the reprojection form keeps all 8.
    EXPECT_GE(p.depth_inliers, reprojection ? 8 : 7);
    EXPECT_LE(p.depth_inliers, 8);
    EXPECT_LT(translation_error_m(p.T_j_i, s.T_j_i), 0.01);
  }
}

std::vector<TranslationObservation> depth_observations(const TwoViewScene& s) {
  std::vector<TranslationObservation> obs;
  for (const auto& c : s.correspondences)
    if (c.depth_i) obs.push_back({*c.depth_i * Vec3(c.m_i.x(), c.m_i.y(), 1.0), c.m_j});
  return obs;
}

TEST(PoseChange, Eq3ClosedFormIsExactOnNoiseFreeData) {
  TwoViewSceneOptions so;
  so.pixel_noise_px = 0.0;
  so.depth_features = 2;
  const TwoViewScene s = make_two_view_scene(step_pose(), so);
  const auto obs = depth_observations(s);
  ASSERT_EQ(obs.size(), 2u);
  const auto t = translation_least_squares(s.T_j_i.rotation(), obs);
  ASSERT_TRUE(t);
  EXPECT_LT((*t - s.T_j_i.t).norm(), 1e-12);
  // eq. 1: Z_j m_j = R P_i + t, so r_k = A_k t - b_k vanishes at the true t.
  EXPECT_FALSE(translation_least_squares(s.T_j_i.rotation(), {obs[0]}));      // 2 equations, 3 unknowns
  EXPECT_FALSE(translation_least_squares(s.T_j_i.rotation(), {obs[0], obs[0]}));  // same feature twice
}

TEST(PoseChange, Eq3LevenbergMarquardtAgreesWithTheClosedForm) {
  TwoViewSceneOptions so;
  so.pixel_noise_px = 1.0;
  so.depth_features = 30;
  so.depth_noise_rel = 0.01;
  const TwoViewScene s = make_two_view_scene(step_pose(), so);
  const auto obs = depth_observations(s);
  const Mat3 R = s.T_j_i.rotation();
  const auto t_ls = translation_least_squares(R, obs);
  ASSERT_TRUE(t_ls);
  // Plain least squares from a start 1 m away: LM must land on the closed-form minimum.
  const Vec3 t_lm = translation_levenberg_marquardt(R, obs, *t_ls + Vec3(1.0, -0.5, 0.7), 0.0);
  EXPECT_LT((t_lm - *t_ls).norm(), 1e-9);
  // With the Huber loss and no outliers, the robust minimum moves by far less than the noise.
  const Vec3 t_huber = translation_levenberg_marquardt(R, obs, *t_ls, 1.0, so.focal_px);
  EXPECT_LT((t_huber - *t_ls).norm(), 5e-3);
  EXPECT_GT((*t_ls - s.T_j_i.t).norm(), 1e-5);  // the data is noisy: the check above is not trivial
}

double reprojection_sse(const Mat3& R, const Vec3& t, const std::vector<TranslationObservation>& obs) {
  double sse = 0;
  for (const auto& o : obs) {
    const Vec3 X = R * o.P_i + t;
    sse += (X.head<2>() / X.z() - o.m_j).squaredNorm();
  }
  return sse;
}

TEST(PoseChange, ReprojectionFormMinimizesTheReprojectionError) {
  TwoViewSceneOptions so;
  so.pixel_noise_px = 1.0;
  so.depth_features = 25;
  so.depth_noise_rel = 0.01;
  const TwoViewScene s = make_two_view_scene(step_pose(), so);
  const auto obs = depth_observations(s);
  const Mat3 R = s.T_j_i.rotation();
  const Vec3 t_alg = *translation_least_squares(R, obs);
  const Vec3 t_rep = translation_levenberg_marquardt(R, obs, t_alg, 0.0, so.focal_px, true);
  EXPECT_LE(reprojection_sse(R, t_rep, obs), reprojection_sse(R, t_alg, obs));
  // At its minimum the gradient of the reprojection SSE vanishes (central differences).
  for (int a = 0; a < 3; ++a) {
    Vec3 d = Vec3::Zero();
    d[a] = 1e-6;
    const double g = (reprojection_sse(R, t_rep + d, obs) - reprojection_sse(R, t_rep - d, obs)) / 2e-6;
    EXPECT_NEAR(g, 0.0, 1e-6) << a;
  }
  EXPECT_GT((t_rep - t_alg).norm(), 1e-6);  // the two objectives differ on noisy data
}

TEST(PoseChange, HuberLossResistsAnOutlierThatLeastSquaresFollows) {
  TwoViewSceneOptions so;
  so.pixel_noise_px = 0.2;
  so.depth_features = 12;
  const TwoViewScene s = make_two_view_scene(step_pose(), so);
  auto obs = depth_observations(s);
  obs[3].m_j += Vec2(40.0, -25.0) / so.focal_px;
  const Mat3 R = s.T_j_i.rotation();
  const Vec3 t_ls = *translation_least_squares(R, obs);
  const Vec3 t_huber = translation_levenberg_marquardt(R, obs, t_ls, 1.0, so.focal_px);
  EXPECT_LT((t_huber - s.T_j_i.t).norm(), 0.5 * (t_ls - s.T_j_i.t).norm());
}

TEST(PoseChange, PureRotationKeepsTheRotationRight) {
  for (double t_norm : {0.0, 0.002}) {
    const SE3 T(quat_from_rpy(1.0 * kDeg, 4.0 * kDeg, -7.0 * kDeg), Vec3(t_norm, 0.0, 0.0));
    TwoViewSceneOptions so;
    so.depth_features = 20;
    so.min_depth_m = 2.0;
    const TwoViewScene s = make_two_view_scene(T, so);
    const PoseChange p = expect_pose(s, PoseChangeMethod::kHybrid);
    EXPECT_TRUE(p.rotation_only) << t_norm;
    EXPECT_LT(rotation_error_deg(p.T_j_i, T), 0.1) << t_norm;
    EXPECT_LT(translation_error_m(p.T_j_i, T), 0.02) << t_norm;
    EXPECT_GE(p.inliers, 120);
    const PoseChange q = expect_pose(s, PoseChangeMethod::kPnp);
    EXPECT_LT(rotation_error_deg(q.T_j_i, T), 0.2) << t_norm;
    EXPECT_LT(translation_error_m(q.T_j_i, T), 0.02) << t_norm;
  }
}

TEST(PoseChange, FarSceneWithNearDepthFeaturesUsesTheirParallax) {
  // Outdoors: most features 20-60 m away (no depth), a few near ones with depth show the step.
  TwoViewSceneOptions far;
  far.points = 140;
  far.min_depth_m = 20.0;
  far.max_depth_m = 60.0;
  far.depth_features = 0;
  TwoViewSceneOptions near = far;
  near.points = 6;
  near.min_depth_m = 1.5;
  near.max_depth_m = 4.0;
  near.depth_features = -1;
  near.seed = 2;
  TwoViewScene s = make_two_view_scene(step_pose(), far);
  for (const auto& c : make_two_view_scene(step_pose(), near).correspondences) s.correspondences.push_back(c);
  const PoseChange p = expect_pose(s, PoseChangeMethod::kHybrid);
  EXPECT_LT(rotation_error_deg(p.T_j_i, s.T_j_i), 0.15);
  EXPECT_LT(translation_error_m(p.T_j_i, s.T_j_i), 0.03);
  EXPECT_GE(p.depth_inliers, 5);
}

TEST(PoseChange, MalformedInputThrows) {
  const TwoViewScene s = make_two_view_scene(step_pose(), {});
  for (auto m : {PoseChangeMethod::kHybrid, PoseChangeMethod::kPnp}) {
    auto c = s.correspondences;
    c[5].m_j.x() = std::numeric_limits<double>::quiet_NaN();
    EXPECT_NE(navaid::testing::error_message<Error>([&] { estimate_pose_change(c, m, {}); }).find("correspondence 5"),
              std::string::npos);
    c = s.correspondences;
    c[7].depth_i = 0.0;
    EXPECT_NE(navaid::testing::error_message<Error>([&] { estimate_pose_change(c, m, {}); }).find("depth"), std::string::npos);
    c[7].depth_i = -1.0;
    navaid::testing::expect_throw<Error>([&] { estimate_pose_change(c, m, {}); });
    c[7].depth_i = std::numeric_limits<double>::infinity();
    navaid::testing::expect_throw<Error>([&] { estimate_pose_change(c, m, {}); });
  }
  PoseChangeOptions o;
  o.ransac_threshold_px = 0.0;
  EXPECT_EQ(navaid::testing::expect_throw<ConfigError>([&] { estimate_pose_change(s.correspondences, PoseChangeMethod::kHybrid, o); })
                ->key(),
            "ransac_threshold_px");
  o = {};
  o.ransac_confidence = 1.0;
  navaid::testing::expect_throw<ConfigError>([&] { validate(o); });
  o = {};
  o.min_correspondences = 4;
  navaid::testing::expect_throw<ConfigError>([&] { validate(o); });
}

TEST(PoseChange, TooFewCorrespondencesReturnsNullopt) {
  TwoViewSceneOptions so;
  so.points = 6;
  const TwoViewScene s = make_two_view_scene(step_pose(), so);
  std::string why;
  EXPECT_FALSE(estimate_pose_change(s.correspondences, PoseChangeMethod::kHybrid, {}, &why));
  EXPECT_NE(why.find("too few correspondences"), std::string::npos) << why;
  EXPECT_FALSE(estimate_pose_change({}, PoseChangeMethod::kPnp, {}, &why));
}

TEST(PoseChange, DeterministicBySeed) {
  TwoViewSceneOptions so;
  so.outlier_fraction = 0.3;
  so.depth_features = 40;
  so.seed = 9;
  const TwoViewScene s = make_two_view_scene(step_pose(), so);
  for (auto m : {PoseChangeMethod::kHybrid, PoseChangeMethod::kPnp}) {
    PoseChangeOptions o;
    o.seed = 42;
    const PoseChange a = expect_pose(s, m, o), b = expect_pose(s, m, o);
    EXPECT_EQ(a.T_j_i.t, b.T_j_i.t) << to_string(m);
    EXPECT_EQ(a.T_j_i.q.coeffs(), b.T_j_i.q.coeffs()) << to_string(m);
    EXPECT_EQ(a.inlier, b.inlier) << to_string(m);
  }
  // The USAC_ACCURATE variant of the 2D-2D step: accurate and deterministic too.
  PoseChangeOptions u;
  u.essential_usac = true;
  const PoseChange a = expect_pose(s, PoseChangeMethod::kHybrid, u), b = expect_pose(s, PoseChangeMethod::kHybrid, u);
  EXPECT_EQ(a.T_j_i.q.coeffs(), b.T_j_i.q.coeffs());
  EXPECT_EQ(a.inlier, b.inlier);
  EXPECT_LT(rotation_error_deg(a.T_j_i, s.T_j_i), 0.15);
  EXPECT_LT(translation_error_m(a.T_j_i, s.T_j_i), 0.02);
  const TwoViewScene s2 = make_two_view_scene(step_pose(), so);
  EXPECT_EQ(s2.correspondences[17].m_j, s.correspondences[17].m_j);
}

}  // namespace
}  // namespace navaid::estimation
