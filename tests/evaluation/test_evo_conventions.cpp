// evo's conventions (evo_conventions.hpp), against values worked out by hand from evo's rules.
#include <gtest/gtest.h>

#include <cmath>

#include "navaid/core/errors.hpp"
#include "navaid/evaluation/evo_conventions.hpp"
#include "navaid/evaluation/trajectory_evaluation.hpp"

namespace navaid::evaluation {
namespace {

constexpr Timestamp kMs = 1'000'000;

io::StampedPose at(Timestamp t, double x, double yaw_deg = 0.0, double y = 0.0) {
  return {t, SE3(Quat(Eigen::AngleAxisd(yaw_deg * M_PI / 180.0, Vec3::UnitZ())), Vec3(x, y, 0))};
}

TEST(EvoAssociation, NearestWithinMaxDiffFromTheShorterTrajectory) {
  // 3 estimates, 4 ground-truth poses: the estimate is walked. 0 -> 5 ms (5 ms), 100 -> 100, 200 -> 195.
  const std::vector<io::StampedPose> est{at(0, 0), at(100 * kMs, 1), at(200 * kMs, 2)};
  const std::vector<io::StampedPose> gt{at(5 * kMs, 10), at(100 * kMs, 11), at(195 * kMs, 12), at(300 * kMs, 13)};
  auto pairs = associate_poses_evo(est, gt, 10 * kMs);
  ASSERT_EQ(pairs.size(), 3u);
  EXPECT_EQ(pairs[0].t_gt, 5 * kMs);
  EXPECT_EQ(pairs[2].t_gt, 195 * kMs);
  EXPECT_EQ(pairs[2].gt.t.x(), 12.0);
  // max_diff is inclusive: 5 ms passes at 5 ms, not at 4 ms.
  EXPECT_EQ(associate_poses_evo(est, gt, 5 * kMs).size(), 3u);
  pairs = associate_poses_evo(est, gt, 4 * kMs);
  ASSERT_EQ(pairs.size(), 1u);
  EXPECT_EQ(pairs[0].t_est, 100 * kMs);
}

TEST(EvoAssociation, ALongerTrajectorysPoseServesSeveralAndTiesGoToTheFirst) {
  // Two estimates near one ground-truth pose: both take it (rpg's rule would pair only one).
  const std::vector<io::StampedPose> est{at(0, 0), at(1 * kMs, 1)};
  const std::vector<io::StampedPose> gt{at(0, 5), at(1000 * kMs, 6), at(2000 * kMs, 7)};
  const auto pairs = associate_poses_evo(est, gt, 10 * kMs);
  ASSERT_EQ(pairs.size(), 2u);
  EXPECT_EQ(pairs[0].t_gt, 0);
  EXPECT_EQ(pairs[1].t_gt, 0);
  EXPECT_EQ(associate_poses(est, gt, 10 * kMs).size(), 1u);
  // More estimates than ground truth: the ground truth is walked. gt 10 ms lies 10 ms from both
  // estimates 0 and 20: the first wins.
  const std::vector<io::StampedPose> dense{at(0, 0), at(20 * kMs, 1), at(40 * kMs, 2)};
  const std::vector<io::StampedPose> sparse{at(10 * kMs, 9)};
  const auto tie = associate_poses_evo(dense, sparse, 10 * kMs);
  ASSERT_EQ(tie.size(), 1u);
  EXPECT_EQ(tie[0].t_est, 0);
  EXPECT_EQ(tie[0].t_gt, 10 * kMs);
  EXPECT_THROW(associate_poses_evo(est, gt, 0), Error);
}

TEST(EvoRpePairs, Frames) {
  const std::vector<SE3> poses(5);
  EvoRpeOptions o;
  o.delta = 2;
  EXPECT_EQ(evo_rpe_pairs(poses, o), (IndexPairs{{0, 2}, {2, 4}}));
  o.all_pairs = true;
  EXPECT_EQ(evo_rpe_pairs(poses, o), (IndexPairs{{0, 2}, {1, 3}, {2, 4}}));
  o.delta = 1.5;
  EXPECT_THROW(evo_rpe_pairs(poses, o), Error);
  o.delta = 5;
  EXPECT_THROW(evo_rpe_pairs(poses, o), Error);  // no pair: an error, as in evo
}

TEST(EvoRpePairs, MetresConsecutiveStartAtTheFirstPoseToReachDelta) {
  // x = 0, 0.4, 0.9, 1.5, 2.0, 3.1: the path reaches 1 m at index 3 (1.5), then 0.5 + 1.1 at index 5.
  const std::vector<double> x{0, 0.4, 0.9, 1.5, 2.0, 3.1};
  std::vector<SE3> poses;
  for (double v : x) poses.push_back(at(0, v).T_W_B);
  EvoRpeOptions o;
  o.delta = 1.0;
  o.unit = RpeDeltaUnit::kMeters;
  EXPECT_EQ(evo_rpe_pairs(poses, o), (IndexPairs{{3, 5}}));
  // All pairs: for each i the j whose path from i is nearest 1 m: 0 -> 2 (0.9), 1 -> 3 (1.1),
  // 2 -> 4 (1.1), 3 -> 4 (0.5), 4 -> 5 (1.1). Within 0.15 m all but 3 -> 4 pass.
  o.all_pairs = true;
  o.rel_delta_tol = 0.15;
  EXPECT_EQ(evo_rpe_pairs(poses, o), (IndexPairs{{0, 2}, {1, 3}, {2, 4}, {4, 5}}));
  o.rel_delta_tol = 0.05;  // none within 5 cm of 1 m
  EXPECT_THROW(evo_rpe_pairs(poses, o), Error);
}

TEST(EvoRpePairs, Angles) {
  // Yaw 0, 10, 25, 40, 55 degrees: steps 10, 15, 15, 15. Consecutive with 20 degrees: 10 + 15 = 25
  // closes (0, 2), then 15 + 15 = 30 closes (2, 4).
  std::vector<SE3> poses;
  for (double yaw : {0.0, 10.0, 25.0, 40.0, 55.0}) poses.push_back(at(0, 0, yaw).T_W_B);
  EvoRpeOptions o;
  o.delta = 20;
  o.unit = RpeDeltaUnit::kDegrees;
  EXPECT_EQ(evo_rpe_pairs(poses, o), (IndexPairs{{0, 2}, {2, 4}}));
  // All pairs within 2 degrees of 30: (10, 40) and (25, 55).
  o.delta = 30;
  o.all_pairs = true;
  o.rel_delta_tol = 2.0 / 30.0;
  EXPECT_EQ(evo_rpe_pairs(poses, o), (IndexPairs{{1, 3}, {2, 4}}));
  // The same in radians.
  o.delta = 30 * M_PI / 180.0;
  o.unit = RpeDeltaUnit::kRadians;
  EXPECT_EQ(evo_rpe_pairs(poses, o), (IndexPairs{{1, 3}, {2, 4}}));
  o.delta = 200;
  o.unit = RpeDeltaUnit::kDegrees;
  EXPECT_THROW(evo_rpe_pairs(poses, o), Error);
}

// Ground truth on a straight line x = i; the estimate stretched by 1.1 and turned by 30 degrees.
struct Stretched {
  std::vector<io::StampedPose> est, gt;
  Stretched() {
    const Quat turn(Eigen::AngleAxisd(M_PI / 6, Vec3::UnitZ()));
    for (int i = 0; i < 6; ++i) {
      gt.push_back(at(i * 100 * kMs, i, 0, 0.2 * (i % 2)));
      const Vec3 p = turn * (1.1 * gt.back().T_W_B.t);
      est.push_back({gt.back().t, SE3(turn, p)});
    }
  }
};

TEST(EvoRpe, TranslationOfTheRelativeErrorAndTheScaleCorrection) {
  const Stretched s;
  EvaluationOptions o;
  o.ate.alignment = AlignmentMode::kNone;
  o.evo_max_diff = 10 * kMs;
  o.evo_rpe = EvoRpeOptions{};  // delta 1 frame
  auto e = evaluate_trajectory(s.est, s.gt, o);
  EXPECT_EQ(e.association, "evo");
  ASSERT_TRUE(e.evo_rpe);
  ASSERT_EQ(e.evo_rpe->pairs.size(), 5u);
  // Pair (0, 1): gt moves (1, 0.2), the estimate 1.1 x that in its own turned frame, so relative
  // to each start both see the same direction: E = 0.1 * |(1, 0.2)|.
  EXPECT_NEAR(e.evo_rpe->translation_errors[0], 0.1 * std::hypot(1.0, 0.2), 1e-12);
  EXPECT_NEAR(e.evo_rpe->rotation_errors_rad[0], 0.0, 1e-12);
  // -s alone: evo's scale-only correction (1 / 1.1) removes the error entirely; no rotation applied.
  o.ate.alignment = AlignmentMode::kScale;
  e = evaluate_trajectory(s.est, s.gt, o);
  EXPECT_NEAR(e.ate.transform.scale, 1.0 / 1.1, 1e-12);
  EXPECT_TRUE(e.ate.transform.R.isIdentity(1e-15));
  EXPECT_TRUE(e.ate.transform.t.isZero(1e-15));
  EXPECT_NEAR(e.evo_rpe->translation.max, 0.0, 1e-12);
  // -as: Sim(3) also removes the absolute error.
  o.ate.alignment = AlignmentMode::kSim3;
  e = evaluate_trajectory(s.est, s.gt, o);
  EXPECT_NEAR(e.ate.position.max, 0.0, 1e-9);
}

TEST(EvoRpe, PairsChosenOnTheEstimateOrTheReference) {
  // The estimate travels 1.1 m per step, the reference 1 m: with delta 2.1 m the estimate's path
  // reaches it at index 2 (2.2 m) and the reference's at index 3 (3 m).
  std::vector<io::StampedPose> est, gt;
  for (int i = 0; i < 8; ++i) {
    gt.push_back(at(i * 100 * kMs, i));
    est.push_back(at(i * 100 * kMs, 1.1 * i));
  }
  EvaluationOptions o;
  o.ate.alignment = AlignmentMode::kNone;
  EvoRpeOptions r;
  r.delta = 2.1;
  r.unit = RpeDeltaUnit::kMeters;
  o.evo_rpe = r;
  auto e = evaluate_trajectory(est, gt, o);
  EXPECT_EQ(e.evo_rpe->pairs, (IndexPairs{{2, 4}, {4, 6}}));
  EXPECT_NEAR(e.evo_rpe->translation_errors[0], 0.2, 1e-12);
  o.evo_rpe->pairs_from_reference = true;
  e = evaluate_trajectory(est, gt, o);
  EXPECT_EQ(e.evo_rpe->pairs, (IndexPairs{{3, 6}}));
  EXPECT_NEAR(e.evo_rpe->translation_errors[0], 0.3, 1e-12);
}

}  // namespace
}  // namespace navaid::evaluation
