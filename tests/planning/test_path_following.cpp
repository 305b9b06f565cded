// Path following (eLabrador Alg. 2): look-ahead along the path, shortened to the first obstacle
// on the straight line to it, blocked when nothing is left.
#include <gtest/gtest.h>

#include <cmath>
#include <utility>

#include "navaid/planning/path_follower.hpp"

namespace navaid::planning {
namespace {

using mapping::Cell2;
using mapping::CostMap;
using mapping::GridGeometry;

CostMap empty_map() { return CostMap(GridGeometry(Cell2(-50, -50), 100, 100, 0.1), 0.9, 0.0); }

std::vector<Vec2> straight_path(Vec2 a, Vec2 b, int n) {
  std::vector<Vec2> p;
  for (int i = 0; i <= n; ++i) p.push_back(a + (b - a) * (static_cast<double>(i) / n));
  return p;
}

TEST(PathFollowing, FirstObstacleAlongKnownDistances) {
  CostMap m = empty_map();
  for (int y = 0; y < 100; ++y) m.at(60, y) = 1.0F;  // wall: cells x in [1.0, 1.1) m
  EXPECT_NEAR(*first_obstacle_along(m, {0.05, 0.05}, {2.0, 0.05}), 0.95, 1e-9);
  EXPECT_NEAR(*first_obstacle_along(m, {0.0, 0.0}, {2.0, 2.0}), std::sqrt(2.0), 1e-9);  // diagonal
  EXPECT_FALSE(first_obstacle_along(m, {0.05, 0.05}, {0.95, 3.0}).has_value());
  EXPECT_FALSE(first_obstacle_along(m, {2.0, 0.05}, {4.0, 0.05}).has_value());  // beyond the wall
  EXPECT_NEAR(*first_obstacle_along(m, {1.05, 0.0}, {3.0, 0.0}), 0.0, 1e-12);   // starts inside
  EXPECT_NEAR(*first_obstacle_along(m, {3.0, 0.05}, {-3.0, 0.05}), 1.9, 1e-9);  // from the other side
  EXPECT_FALSE(first_obstacle_along(m, {0.2, 0.2}, {0.2, 0.2}).has_value());    // a point
}

TEST(PathFollowing, LooksAheadTwoMetresAlongTheNearestPart) {
  const CostMap m = empty_map();
  const std::vector<Vec2> path = straight_path({-4.0, 0.0}, {4.0, 0.0}, 80);
  const FollowStep s = follow_path({-1.0, 0.3}, path, m, PathFollowerConfig{});
  EXPECT_FALSE(s.blocked);
  EXPECT_EQ(s.nearest_index, 30U);
  EXPECT_NEAR(s.distance_to_path_m, 0.3, 1e-9);
  EXPECT_TRUE(s.next_W.isApprox(Vec2(1.0, 0.0)));
  EXPECT_NEAR(s.foresight_m, 2.0, 1e-12);
  EXPECT_TRUE(s.direction_W.isApprox(Vec2(2.0, -0.3)));
  // Near the end the look-ahead stops at the last point.
  const FollowStep end = follow_path({3.5, 0.0}, path, m, PathFollowerConfig{});
  EXPECT_TRUE(end.at_end);
  EXPECT_TRUE(end.next_W.isApprox(Vec2(4.0, 0.0)));
  EXPECT_FALSE(end.blocked);
}

TEST(PathFollowing, ShortensTheForesightToTheObstacle) {
  // The path goes round a box; the user, strayed below the path, would cut the corner into it.
  CostMap m = empty_map();
  for (int y = 45; y < 59; ++y)
    for (int x = 58; x < 62; ++x) m.at(x, y) = 1.0F;  // box x in [0.8, 1.2), y in [-0.5, 0.9)
  std::vector<Vec2> path = straight_path({0.0, 0.0}, {0.0, 1.0}, 10);
  for (const auto& [a, b] : {std::pair<Vec2, Vec2>{{0.0, 1.0}, {2.0, 1.0}}, {{2.0, 1.0}, {2.0, 0.0}}}) {
    const std::vector<Vec2> leg = straight_path(a, b, static_cast<int>(std::lround((b - a).norm() * 10)));
    path.insert(path.end(), leg.begin() + 1, leg.end());
  }
  const FollowStep s = follow_path({0.3, 0.0}, path, m, PathFollowerConfig{});
  EXPECT_EQ(s.nearest_index, 0U);
  EXPECT_TRUE(first_obstacle_along(m, {0.3, 0.0}, Vec2(1.0, 1.0)).has_value());  // the unshortened look-ahead
  EXPECT_FALSE(s.blocked);
  EXPECT_LT(s.foresight_m, 2.0);
  EXPECT_FALSE(first_obstacle_along(m, {0.3, 0.0}, s.next_W).has_value());
  // Right in front of the box with a path through it: nothing is left, stop.
  const std::vector<Vec2> through = straight_path({0.5, 0.0}, {3.0, 0.0}, 25);  // into the box
  const FollowStep blocked = follow_path({0.65, 0.0}, through, m, PathFollowerConfig{});
  EXPECT_TRUE(blocked.blocked);
  EXPECT_LT(blocked.foresight_m, 0.3);
}

}  // namespace
}  // namespace navaid::planning
