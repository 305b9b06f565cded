// RPE: sub-trajectory selection by travelled length (rpg's rule) and the relative-pose error.
#include <gtest/gtest.h>

#include <cmath>

#include "navaid/core/errors.hpp"
#include "navaid/evaluation/relative_pose_error.hpp"
#include "synthetic_trajectory.hpp"
#include "test_support.hpp"

using navaid::Error;
using navaid::Quat;
using navaid::SE3;
using navaid::Vec3;
using namespace navaid::evaluation;

namespace {

// Ground truth along x at 1 m spacing (0..10 m); the estimate stretches x by `stretch`.
std::vector<PosePair> straight_line(double stretch, double yaw_rate = 0.0) {
  std::vector<PosePair> pairs;
  for (int i = 0; i <= 10; ++i)
    pairs.push_back({i, i, SE3(navaid::quat_from_rpy(0, 0, yaw_rate * i), Vec3(stretch * i, 0, 0)),
                     SE3(Quat::Identity(), Vec3(i, 0, 0))});
  return pairs;
}

}  // namespace

TEST(Rpe, HandComputedStretchedLine) {
  // L = 2 m: pairs (i, i+2) for i = 0..8; the estimate moved 2.2 m instead of 2: 0.2 m, 10 %.
  const RpeResult r = compute_rpe(straight_line(1.1), 2.0);
  ASSERT_EQ(r.translation.count, 9u);
  for (std::size_t k = 0; k < 9; ++k) EXPECT_EQ(r.end[k], r.start[k] + 2);
  EXPECT_NEAR(r.translation.mean, 0.2, 1e-12);
  EXPECT_NEAR(r.translation.max, 0.2, 1e-12);
  EXPECT_NEAR(r.translation_percent.mean, 10.0, 1e-10);
  EXPECT_EQ(r.rotation_deg.max, 0.0);
  // The Sim(3) scale undoes the stretch.
  EXPECT_LT(compute_rpe(straight_line(1.1), 2.0, 1.0 / 1.1).translation.max, 1e-12);
}

TEST(Rpe, HandComputedHeadingDrift) {
  // The estimate keeps its positions on the line but its heading drifts by 1 deg per metre.
  const double rate = M_PI / 180.0;
  const RpeResult r = compute_rpe(straight_line(1.0, rate), 3.0);
  ASSERT_EQ(r.translation.count, 8u);
  EXPECT_NEAR(r.rotation_deg.mean, 3.0, 1e-9);
  // T_est_i^-1 T_est_j has rotation Rz(3 deg) and translation Rz(-i deg) (3, 0, 0); the ground
  // truth's is (I, (3, 0, 0)); the error's translation is the difference, of norm 6 sin(i deg / 2).
  for (std::size_t k = 0; k < r.start.size(); ++k)
    EXPECT_NEAR(r.translation_errors[k], 6.0 * std::sin(r.start[k] * rate / 2.0), 1e-12) << k;
}

TEST(Rpe, RigidMotionAndTimingDoNotMatter) {
  const auto gt = navaid::testing::synthetic_trajectory(150);
  const auto est = navaid::testing::in_frame(gt, SE3(navaid::quat_from_rpy(0.3, 0.1, 2.0), Vec3(1, 2, 3)));
  std::vector<PosePair> pairs;
  for (std::size_t i = 0; i < gt.size(); ++i) pairs.push_back({est[i].t, gt[i].t, est[i].T_W_B, gt[i].T_W_B});
  for (double L : {0.5, 2.0, 5.0}) {
    const RpeResult r = compute_rpe(pairs, L);
    EXPECT_GT(r.translation.count, 10u) << L;
    EXPECT_LT(r.translation.max, 1e-9) << L;
    EXPECT_LT(r.rotation_deg.max, 1e-6) << L;
  }
}

TEST(Rpe, LengthToleranceAndTies) {
  // L = 2.5 m on 1 m spacing: ends i+2 and i+3 are both 0.5 m off. Default tolerance 0.2 L = 0.5
  // is strict, so nothing fits; a larger one takes the first of the tied ends (as rpg does).
  EXPECT_TRUE(compute_rpe(straight_line(1.1), 2.5).empty());
  const RpeResult r = compute_rpe(straight_line(1.1), 2.5, 1.0, 0.6);
  ASSERT_FALSE(r.empty());
  EXPECT_EQ(r.start.front(), 0u);
  EXPECT_EQ(r.end.front(), 2u);
  EXPECT_EQ(r.end.back(), 10u);
  EXPECT_EQ(r.start.back(), 8u);
  EXPECT_TRUE(compute_rpe(straight_line(1.0), 20.0).empty());  // longer than the path
}

TEST(Rpe, PathLengthAndPercentages) {
  const auto d = cumulative_path_length({{0, 0, 0}, {3, 4, 0}, {3, 4, 0}, {3, 4, 2}});
  EXPECT_EQ(d, (std::vector<double>{0.0, 5.0, 5.0, 7.0}));
  EXPECT_EQ(lengths_from_percentages(123.456, {10, 50}), (std::vector<double>{12.34, 61.72}));
  EXPECT_THROW(lengths_from_percentages(10.0, {0.0}), Error);
  EXPECT_THROW(lengths_from_percentages(10.0, {120.0}), Error);
  EXPECT_THROW(compute_rpe(straight_line(1.0), 0.0), Error);
  EXPECT_THROW(compute_rpe(straight_line(1.0), std::nan("")), Error);
  EXPECT_THROW(compute_rpe(straight_line(1.0), 1.0, -1.0), Error);
}
