// The planner comparison protocol: pairs drawn from a seed are deterministic, free, far enough
// apart and connected; every planner runs on every pair; the summary statistics.
#include <gtest/gtest.h>

#include "navaid/core/errors.hpp"
#include "navaid/experiments/planner_comparison.hpp"
#include "navaid/planning/grid_astar.hpp"

namespace navaid::experiments {
namespace {

mapping::CostMap two_rooms() {
  // 10 x 6 m at 0.1 m, a wall at x = 5 m with a door at y 2.5-3.7 m, and a closed box.
  mapping::CostMap m(mapping::GridGeometry(mapping::Cell2(0, 0), 100, 60, 0.1), 0.9, 0.0);
  for (int y = 0; y < 60; ++y)
    if (y < 25 || y >= 37) m.at(50, y) = 1.0F;
  for (int x = 80; x < 96; ++x) m.at(x, 50) = m.at(x, 58) = 1.0F;
  for (int y = 50; y < 59; ++y) m.at(80, y) = m.at(95, y) = 1.0F;
  return m;
}

TEST(PlannerComparison, PairsAreDeterministicFreeFarAndConnected) {
  const mapping::CostMap m = two_rooms();
  mapping::Esdf2d esdf;
  esdf.update(m);
  const planning::GridAStarPlanner astar;
  PairSampling s;
  s.pairs = 8;
  s.min_distance_m = 4.0;
  s.clearance_m = 0.3;
  const std::vector<PlannerPair> a = sample_planner_pairs(m, esdf, astar, s);
  const std::vector<PlannerPair> b = sample_planner_pairs(m, esdf, astar, s);
  ASSERT_EQ(a.size(), 8U);
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].start.position, b[i].start.position);
    EXPECT_EQ(a[i].goal, b[i].goal);
    EXPECT_GE((a[i].goal - a[i].start.position).norm(), 4.0);
    EXPECT_GE(*esdf.distance(a[i].start.position), 0.3);
    EXPECT_GE(*esdf.distance(a[i].goal), 0.3);
  }
  s.seed = 2;
  EXPECT_NE(sample_planner_pairs(m, esdf, astar, s)[0].goal, a[0].goal);
  const auto runs = run_planners(m, esdf, {&astar, &astar}, a);
  ASSERT_EQ(runs.size(), 2U);
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_TRUE(runs[0][i].found);  // the sampler kept connected pairs only (none in the closed box)
    EXPECT_EQ(runs[0][i].expanded, runs[1][i].expanded);
    EXPECT_GE(runs[0][i].length_m, 4.0 - 0.2);
  }
  // A distance no pair can have: a clear error, not a hang.
  s.min_distance_m = 50.0;
  s.max_attempts = 2000;
  EXPECT_THROW(sample_planner_pairs(m, esdf, astar, s), Error);
}

TEST(PlannerComparison, Summary) {
  const Summary3 s = summarize({1.0, 2.0, 4.0});
  EXPECT_DOUBLE_EQ(s.avg, 7.0 / 3.0);
  EXPECT_NEAR(s.std, std::sqrt(((1 - 7.0 / 3) * (1 - 7.0 / 3) + (2 - 7.0 / 3) * (2 - 7.0 / 3) + (4 - 7.0 / 3) * (4 - 7.0 / 3)) / 2.0),
              1e-12);
  EXPECT_DOUBLE_EQ(s.max, 4.0);
  EXPECT_DOUBLE_EQ(summarize({3.0}).std, 0.0);
  EXPECT_THROW(summarize({}), Error);
}

}  // namespace
}  // namespace navaid::experiments
