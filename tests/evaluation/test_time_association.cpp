// Time association: the closest-first, each-pose-once rule with a strict tolerance.
#include <gtest/gtest.h>

#include <vector>

#include "navaid/core/errors.hpp"
#include "navaid/evaluation/time_association.hpp"
#include "synthetic_trajectory.hpp"
#include "test_support.hpp"

using navaid::Error;
using navaid::Timestamp;
using namespace navaid::evaluation;

namespace {

constexpr Timestamp kMs = 1'000'000;

std::vector<std::pair<std::size_t, std::size_t>> as_pairs(const std::vector<TimeMatch>& m) {
  std::vector<std::pair<std::size_t, std::size_t>> out;
  for (const auto& x : m) out.emplace_back(x.est, x.gt);
  return out;
}

using Pairs = std::vector<std::pair<std::size_t, std::size_t>>;

}  // namespace

TEST(TimeAssociation, NearestGroundTruthForSparseEstimates) {
  // Ground truth at 200 Hz, estimates at 10 Hz jittered by up to 2 ms: each takes its nearest.
  std::vector<Timestamp> gt, est;
  for (int i = 0; i < 400; ++i) gt.push_back(i * 5 * kMs);
  for (int i = 0; i < 19; ++i) est.push_back(i * 100 * kMs + (i % 5 - 2) * kMs / 2 + 3 * kMs);
  const auto m = associate_by_time(est, gt);
  ASSERT_EQ(m.size(), est.size());
  for (std::size_t k = 0; k < m.size(); ++k) {
    EXPECT_EQ(m[k].est, k);
    const Timestamp dt = std::abs(est[k] - gt[m[k].gt]);
    EXPECT_LE(dt, 5 * kMs / 2) << k;
    if (m[k].gt > 0) {
      EXPECT_LE(dt, std::abs(est[k] - gt[m[k].gt - 1]));
    }
    if (m[k].gt + 1 < gt.size()) {
      EXPECT_LE(dt, std::abs(est[k] - gt[m[k].gt + 1]));
    }
  }
}

TEST(TimeAssociation, ToleranceIsStrict) {
  const std::vector<Timestamp> gt{0, 1000 * kMs};
  EXPECT_TRUE(associate_by_time({20 * kMs}, gt, 20 * kMs).empty());   // ground truth 20 ms earlier
  EXPECT_TRUE(associate_by_time({980 * kMs}, gt, 20 * kMs).empty());  // ground truth 20 ms later
  EXPECT_EQ(as_pairs(associate_by_time({20 * kMs - 1}, gt, 20 * kMs)), (Pairs{{0, 0}}));
  EXPECT_EQ(as_pairs(associate_by_time({1000 * kMs - 20 * kMs + 1}, gt, 20 * kMs)), (Pairs{{0, 1}}));
  EXPECT_TRUE(associate_by_time({500 * kMs}, gt).empty());
}

TEST(TimeAssociation, EachGroundTruthPoseUsedOnce) {
  // Two estimates compete for gt 0 (at 0 ms): the closer (2 ms) wins; the other (5 ms) falls back
  // to gt 1 (at 30 ms, 25 ms away) only when that is within tolerance.
  const std::vector<Timestamp> gt{0, 30 * kMs};
  const std::vector<Timestamp> est{2 * kMs, 5 * kMs};
  EXPECT_EQ(as_pairs(associate_by_time(est, gt, 20 * kMs)), (Pairs{{0, 0}}));
  EXPECT_EQ(as_pairs(associate_by_time(est, gt, 30 * kMs)), (Pairs{{0, 0}, {1, 1}}));
  // Globally closest first, not estimate order: est 0 (at 8 ms) would take gt 1 (10 ms) first if
  // matched greedily in time order, but est 1 (at 10 ms) is exactly on it.
  EXPECT_EQ(as_pairs(associate_by_time({8 * kMs, 10 * kMs}, {0, 10 * kMs}, 20 * kMs)), (Pairs{{0, 0}, {1, 1}}));
}

TEST(TimeAssociation, TiesGoToTheLowerIndex) {
  // An estimate exactly between two ground-truth poses takes the earlier one.
  EXPECT_EQ(as_pairs(associate_by_time({5 * kMs}, {0, 10 * kMs})), (Pairs{{0, 0}}));
  // Two estimates equally far from one ground-truth pose: the earlier estimate gets it.
  EXPECT_EQ(as_pairs(associate_by_time({-3 * kMs, 3 * kMs}, {0})), (Pairs{{0, 0}}));
}

TEST(TimeAssociation, EmptyInputsAndBadArguments) {
  EXPECT_TRUE(associate_by_time({}, {0, 1}).empty());
  EXPECT_TRUE(associate_by_time({0, 1}, {}).empty());
  EXPECT_NE(navaid::testing::error_message<Error>([] { associate_by_time({2, 1}, {0}); }).find("estimate times decrease"),
            std::string::npos);
  EXPECT_NE(navaid::testing::error_message<Error>([] { associate_by_time({0}, {0, 5, 3}); }).find("ground-truth"),
            std::string::npos);
  EXPECT_NE(navaid::testing::error_message<Error>([] { associate_by_time({0}, {0}, 0); }).find("tolerance"),
            std::string::npos);
}

TEST(TimeAssociation, PosesCarryTheirMatchedPartners) {
  const auto gt = navaid::testing::synthetic_trajectory(50, 10 * kMs);
  std::vector<navaid::io::StampedPose> est;
  for (std::size_t i = 0; i < gt.size(); i += 7) est.push_back({gt[i].t + 1 * kMs, gt[i].T_W_B});
  const auto pairs = associate_poses(est, gt);
  ASSERT_EQ(pairs.size(), est.size());
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    EXPECT_EQ(pairs[k].t_est, est[k].t);
    EXPECT_EQ(pairs[k].t_gt, gt[7 * k].t);
    EXPECT_TRUE(pairs[k].gt.is_approx(gt[7 * k].T_W_B, 0.0));
  }
}
