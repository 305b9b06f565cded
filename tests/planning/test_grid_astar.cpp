// Grid A* on the search core: optimal against an independent Dijkstra on random cost maps,
// clear reasons for every way a search cannot start or finish, limits that stop it.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <random>

#include "navaid/core/errors.hpp"
#include "navaid/planning/grid_astar.hpp"

namespace navaid::planning {
namespace {

using mapping::Cell2;
using mapping::CostMap;
using mapping::GridGeometry;

CostMap random_map(int w, int h, double obstacle_fraction, std::uint32_t seed) {
  CostMap m(GridGeometry(Cell2(0, 0), w, h, 0.1), 0.9, 0.0);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) m.at(x, y) = u(rng) < obstacle_fraction ? 1.0F : static_cast<float>(0.9 * u(rng));
  return m;
}

// Textbook Dijkstra with the same moves and edge costs, written independently of the core.
double dijkstra(const CostMap& m, Cell2 s, Cell2 t, const GridCostConfig& c) {
  const int w = m.geometry().width();
  const int h = m.geometry().height();
  const double r = m.geometry().resolution();
  std::vector<double> dist(static_cast<std::size_t>(w * h), std::numeric_limits<double>::infinity());
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> q;
  const auto free = [&](int x, int y) { return x >= 0 && y >= 0 && x < w && y < h && !m.is_obstacle(x, y); };
  dist[static_cast<std::size_t>(s.y() * w + s.x())] = 0.0;
  q.emplace(0.0, s.y() * w + s.x());
  while (!q.empty()) {
    const auto [d, i] = q.top();
    q.pop();
    if (d > dist[static_cast<std::size_t>(i)]) continue;
    const int x = i % w;
    const int y = i / w;
    if (x == t.x() && y == t.y()) return d;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        if ((dx == 0 && dy == 0) || !free(x + dx, y + dy)) continue;
        if (dx != 0 && dy != 0 && (!free(x + dx, y) || !free(x, y + dy))) continue;
        const double step = (dx != 0 && dy != 0) ? r * std::sqrt(2.0) : r;
        const double nd = d + step * (c.length_weight + c.cost_weight * m.at(x + dx, y + dy));
        const int n = (y + dy) * w + x + dx;
        if (nd < dist[static_cast<std::size_t>(n)]) {
          dist[static_cast<std::size_t>(n)] = nd;
          q.emplace(nd, n);
        }
      }
  }
  return std::numeric_limits<double>::infinity();
}

PlanningProblem problem_on(const CostMap& m, Vec2 start, Vec2 goal) {
  PlanningProblem p;
  p.cost = &m;
  p.start.position = start;
  p.goal_W = goal;
  return p;
}

TEST(GridAStar, OptimalAgainstDijkstraOnRandomMaps) {
  int found = 0;
  int unreachable = 0;
  for (std::uint32_t seed = 1; seed <= 40; ++seed) {
    const CostMap m = random_map(40, 30, 0.25, seed);
    std::mt19937 rng(seed * 7919U);
    std::uniform_int_distribution<int> ux(0, 39);
    std::uniform_int_distribution<int> uy(0, 29);
    const auto random_cell = [&] {
      const int y = uy(rng);  // y before x: the order of record (random_draws.hpp)
      return Cell2(ux(rng), y);
    };
    Cell2 s = random_cell();
    Cell2 t = random_cell();
    while (m.is_obstacle(s)) s = random_cell();
    while (m.is_obstacle(t)) t = random_cell();
    GridAStarConfig config;
    config.cost.cost_weight = seed % 2 == 0 ? 1.0 : 3.0;
    const Plan plan = GridAStarPlanner(config).plan(
        problem_on(m, m.geometry().cell_center(s), m.geometry().cell_center(t)));
    const double reference = dijkstra(m, s, t, config.cost);
    if (std::isinf(reference)) {
      EXPECT_EQ(plan.reason, GuidanceReason::kNoPath) << seed;
      ++unreachable;
      continue;
    }
    ASSERT_TRUE(plan.found()) << seed << " " << plan.detail;
    EXPECT_NEAR(plan.cost, reference, 1e-9) << seed;
    ++found;
    // The path is connected by 8-neighbour steps and stays off obstacles.
    for (std::size_t i = 1; i < plan.path_W.size(); ++i) {
      EXPECT_LE((plan.path_W[i] - plan.path_W[i - 1]).norm(), 0.1 * std::sqrt(2.0) + 1e-9);
      EXPECT_FALSE(m.is_obstacle(m.geometry().cell_of(plan.path_W[i])));
    }
    EXPECT_TRUE(plan.path_W.front().isApprox(m.geometry().cell_center(s)));
    EXPECT_TRUE(plan.path_W.back().isApprox(m.geometry().cell_center(t)));
  }
  EXPECT_GT(found, 25);  // the sample covers both outcomes
  EXPECT_GT(unreachable + found, 39);
}

TEST(GridAStar, StraightLineOnAnEmptyMapHasTheOctileLength) {
  CostMap m(GridGeometry(Cell2(0, 0), 50, 50, 0.1), 0.9, 0.0);
  const Plan plan = GridAStarPlanner().plan(problem_on(m, {0.05, 0.05}, {3.05, 1.05}));
  ASSERT_TRUE(plan.found());
  EXPECT_NEAR(plan.length_m, 2.0 + 1.0 * std::sqrt(2.0), 1e-9);  // 20 straight + 10 diagonal steps
  EXPECT_NEAR(plan.cost, plan.length_m, 1e-9);                     // alpha 1, zero map cost
}

TEST(GridAStar, ReasonsForEveryWayItCannotPlan) {
  CostMap m(GridGeometry(Cell2(0, 0), 20, 20, 0.1), 0.9, 0.0);
  for (int i = 0; i < 20; ++i) m.at(10, i) = 1.0F;  // a wall across the map
  const GridAStarPlanner astar;
  EXPECT_EQ(astar.plan(problem_on(m, {-0.5, 0.5}, {1.5, 0.5})).reason, GuidanceReason::kOffMap);
  EXPECT_EQ(astar.plan(problem_on(m, {0.5, 0.5}, {5.0, 0.5})).reason, GuidanceReason::kOffMap);
  EXPECT_EQ(astar.plan(problem_on(m, {1.05, 0.5}, {0.5, 0.5})).reason, GuidanceReason::kStartBlocked);
  EXPECT_EQ(astar.plan(problem_on(m, {0.5, 0.5}, {1.05, 0.5})).reason, GuidanceReason::kGoalBlocked);
  const Plan none = astar.plan(problem_on(m, {0.5, 0.5}, {1.5, 0.5}));
  EXPECT_EQ(none.reason, GuidanceReason::kNoPath);
  EXPECT_EQ(none.expanded, 200U);  // exactly the left half, 10 x 20 cells
  EXPECT_FALSE(none.detail.empty());

  GridAStarConfig limited;
  limited.limits.max_expansions = 30;
  const Plan stopped = GridAStarPlanner(limited).plan(problem_on(m, {0.05, 0.05}, {0.95, 1.95}));
  EXPECT_EQ(stopped.reason, GuidanceReason::kSearchLimit);
  EXPECT_EQ(stopped.expanded, 30U);

  PlanningProblem no_goal = problem_on(m, {0.5, 0.5}, {0.5, 0.5});
  no_goal.goal_W.reset();
  EXPECT_THROW(astar.plan(no_goal), Error);
  PlanningProblem no_map = problem_on(m, {0.5, 0.5}, {0.5, 0.5});
  no_map.cost = nullptr;
  EXPECT_THROW(astar.plan(no_map), Error);
}

TEST(GridAStar, ClearanceGrowsWithPositionSigma) {
  // A pillar between start and goal: the more unsure the position, the wider the berth.
  CostMap m(GridGeometry(Cell2(0, 0), 80, 40, 0.1), 0.9, 0.0);
  for (int y = 17; y < 23; ++y)
    for (int x = 37; x < 43; ++x) m.at(x, y) = 1.0F;
  GridAStarConfig config;
  config.cost.base_clearance_m = 0.2;
  config.cost.clearance_k_sigma = 2.0;
  const auto min_distance_to_pillar = [&](const Plan& p) {
    double best = 1e9;
    for (const Vec2& q : p.path_W) {
      const Vec2 d = (q - Vec2(4.0, 2.0)).cwiseAbs() - Vec2(0.3, 0.3);
      best = std::min(best, d.cwiseMax(0.0).norm());
    }
    return best;
  };
  PlanningProblem p = problem_on(m, {0.55, 2.05}, {7.55, 2.05});
  const Plan sure = GridAStarPlanner(config).plan(p);
  p.sigma_xy_m = 0.4;
  const Plan unsure = GridAStarPlanner(config).plan(p);
  ASSERT_TRUE(sure.found());
  ASSERT_TRUE(unsure.found());
  EXPECT_GE(min_distance_to_pillar(sure), 0.2 - 0.05);
  EXPECT_GE(min_distance_to_pillar(unsure), 1.0 - 0.05);
  EXPECT_GT(unsure.length_m, sure.length_m);
  // Too unsure to fit between the pillar and the map's edge... the start itself is blocked.
  p.sigma_xy_m = 5.0;
  EXPECT_EQ(GridAStarPlanner(config).plan(p).reason, GuidanceReason::kStartBlocked);
}

TEST(GridAStar, FactoryKnowsItsPlannersAndRejectsOthers) {
  const Config config;
  EXPECT_EQ(make_local_planner("astar", config)->name(), "astar");
  EXPECT_EQ(make_local_planner("direction-astar", config)->name(), "direction-astar");
  EXPECT_THROW(make_local_planner("dijkstra", config), ConfigError);
}

}  // namespace
}  // namespace navaid::planning
