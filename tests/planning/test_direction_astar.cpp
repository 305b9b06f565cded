// Direction A* (eLabrador Alg. 1, eq. 11): the one search toward all boundary targets finds the
// same best path as Alg. 1's separate searches, the direction term has its known values, and the
// boundary targets are spread along the window's ring.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

#include "navaid/planning/angles.hpp"
#include "navaid/planning/direction_astar.hpp"

namespace navaid::planning {
namespace {

using mapping::Cell2;
using mapping::CostMap;
using mapping::GridGeometry;

TEST(DirectionAStar, DirectionTermKnownValues) {
  const Vec2 c(1.0, 1.0);
  EXPECT_NEAR(direction_term(5.0, 0.0, c, {3.0, 1.0}), 0.0, 1e-12);          // straight ahead
  EXPECT_NEAR(direction_term(5.0, 0.0, c, {1.0, 4.0}), 5.0, 1e-12);          // 90 degrees
  EXPECT_NEAR(direction_term(5.0, 0.0, c, {-2.0, 1.0}), 10.0, 1e-12);        // behind
  EXPECT_NEAR(direction_term(2.0, kPi / 2, c, {2.0, 2.0}), 2.0 * (1.0 - std::cos(kPi / 4)), 1e-12);
  EXPECT_NEAR(direction_term(2.0, -kPi / 2, c, {1.0, -5.0}), 0.0, 1e-12);
}

TEST(DirectionAStar, BoundaryTargetsLieOnTheWindowRingEvenlySpread) {
  const GridGeometry g(Cell2(0, 0), 200, 200, 0.05);
  const CellWindow w = local_window(g, {5.0, 5.0}, 10.0);
  EXPECT_EQ(w.x1 - w.x0, 200);  // 100 cells either side of the centre cell, clipped to the grid
  const CellWindow clipped = local_window(g, {1.0, 5.0}, 10.0);
  EXPECT_EQ(clipped.x0, 0);
  const CellWindow inner{10, 20, 30, 40};
  const std::vector<int> cells = boundary_cells(g, inner, 8);
  ASSERT_EQ(cells.size(), 8U);
  EXPECT_EQ(std::set<int>(cells.begin(), cells.end()).size(), 8U);
  for (const int i : cells) {
    const int x = i % 200;
    const int y = i / 200;
    EXPECT_TRUE(x == 10 || x == 29 || y == 20 || y == 39) << x << "," << y;
  }
  // The ring of a 20 x 20 window has 76 cells; asking for more returns all of them.
  EXPECT_EQ(boundary_cells(g, inner, 1000).size(), 76U);
}

CostMap random_map(int n, double obstacle_fraction, std::uint32_t seed) {
  CostMap m(GridGeometry(Cell2(0, 0), n, n, 0.1), 0.9, 0.0);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) m.at(x, y) = u(rng) < obstacle_fraction ? 1.0F : static_cast<float>(0.8 * u(rng));
  m.at(n / 2, n / 2) = 0.0F;
  return m;
}

TEST(DirectionAStar, OneSearchEqualsTheBestOfTheSeparateSearches) {
  int compared = 0;
  for (std::uint32_t seed = 1; seed <= 30; ++seed) {
    const CostMap m = random_map(61, 0.2 + 0.01 * (seed % 10), seed);
    DirectionAStarConfig config;
    config.window_m = 5.0;
    config.num_targets = 12 + static_cast<int>(seed % 5) * 6;
    config.beta = seed % 3 == 0 ? 0.5 : 4.0;
    PlanningProblem p;
    p.cost = &m;
    p.start.position = m.geometry().cell_center(Cell2(30, 30));
    p.goal_direction_rad = wrap_angle(0.7 * seed);
    const DirectionAStarPlanner planner(config);
    const Plan one = planner.plan(p);
    const Plan separate = planner.plan_separately(p);
    ASSERT_EQ(one.found(), separate.found()) << seed;
    if (!one.found()) continue;
    EXPECT_NEAR(one.cost, separate.cost, 1e-9) << seed;
    EXPECT_LT(one.expanded, separate.expanded) << seed;
    ++compared;
  }
  EXPECT_GE(compared, 25);
}

TEST(DirectionAStar, FollowsTheSubgoalAroundAnObstacle) {
  // A wall ahead (east) with a gap in the north: the path leaves through the east boundary.
  CostMap m(GridGeometry(Cell2(0, 0), 101, 101, 0.1), 0.9, 0.0);
  for (int y = 0; y < 80; ++y) m.at(70, y) = 1.0F;
  PlanningProblem p;
  p.cost = &m;
  p.start.position = m.geometry().cell_center(Cell2(50, 50));
  p.goal_direction_rad = 0.0;
  const Plan plan = DirectionAStarPlanner().plan(p);
  ASSERT_TRUE(plan.found()) << plan.detail;
  EXPECT_GT(plan.path_W.back().x(), 7.0);                    // beyond the wall
  bool passes_gap = false;
  for (const Vec2& q : plan.path_W) passes_gap |= std::abs(q.x() - 7.05) < 0.06 && q.y() > 8.0;
  EXPECT_TRUE(passes_gap);
  // Facing the other way, the path goes west without a detour, to the sampled target nearest to
  // due west (36 targets on a 400-cell ring: 11 cells apart).
  p.goal_direction_rad = kPi;
  const Plan west = DirectionAStarPlanner().plan(p);
  ASSERT_TRUE(west.found());
  EXPECT_LT(west.path_W.back().x(), 0.1);
  EXPECT_LT(west.length_m, 5.0 + 0.6 * (std::sqrt(2.0) - 1.0));
  const Vec2 d = west.path_W.back() - p.start.position;
  EXPECT_LT(std::abs(wrap_angle(std::atan2(d.y(), d.x()) - kPi)), deg_to_rad(8.0));
}

TEST(DirectionAStar, EnclosedStartHasNoPath) {
  CostMap m(GridGeometry(Cell2(0, 0), 41, 41, 0.1), 0.9, 0.0);
  for (int i = 15; i <= 25; ++i) m.at(i, 15) = m.at(i, 25) = m.at(15, i) = m.at(25, i) = 1.0F;
  PlanningProblem p;
  p.cost = &m;
  p.start.position = m.geometry().cell_center(Cell2(20, 20));
  p.goal_direction_rad = 1.0;
  const Plan plan = DirectionAStarPlanner().plan(p);
  EXPECT_EQ(plan.reason, GuidanceReason::kNoPath);
  EXPECT_EQ(plan.expanded, 81U);  // the 9 x 9 room, then nothing
}

}  // namespace
}  // namespace navaid::planning
