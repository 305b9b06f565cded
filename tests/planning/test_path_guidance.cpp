// The eLabrador guidance chain reads the estimate's uncertainty and acts on it: no direction
// while locating, none while the route registration is unsure, lower confidence and a wider
// berth as the position sigma grows; re-plans when the map or the subgoal changes.
#include <gtest/gtest.h>

#include <cmath>

#include "navaid/planning/angles.hpp"
#include "navaid/planning/direction_astar.hpp"
#include "navaid/planning/path_guidance.hpp"
#include "planar_estimate.hpp"

namespace navaid::planning {
namespace {

using mapping::Cell2;
using mapping::CostMap;
using mapping::GridGeometry;

CostMap open_map() { return CostMap(GridGeometry(Cell2(-50, -50), 100, 100, 0.1), 0.9, 0.0); }

PathGuidance guidance(const std::string& planner = "astar", PathGuidanceConfig config = {}) {
  config.scope = mapping::UncertaintyScope::kAbsolute;
  return PathGuidance(config, make_local_planner(planner, Config()));
}

TEST(PathGuidance, HeadingIsRelativeToTheUser) {
  const CostMap m = open_map();
  PathGuidance g = guidance();
  Subgoal goal;
  goal.goal_W = Vec2(4.0, 0.05);
  // Facing north (+y), the goal lies east: turn right by 90 degrees.
  const GuidanceCommand c = g.update(planar_estimate({0.05, 0.05}, kPi / 2, 0.01, 0.001), m, nullptr, goal);
  ASSERT_EQ(c.action, GuidanceAction::kGo) << c.detail;
  EXPECT_NEAR(*c.heading_rad, -kPi / 2, 1e-9);
  EXPECT_NEAR(*c.lookahead_m, 2.0, 1e-9);
  EXPECT_GT(c.confidence, 0.9);
  EXPECT_EQ(g.stats().plans, 1U);
  // Within the arrival radius.
  EXPECT_EQ(g.update(planar_estimate({3.8, 0.05}, 0.0, 0.01, 0.001), m, nullptr, goal).action, GuidanceAction::kArrived);
}

TEST(PathGuidance, OnArrivalTheCommandSaysWhereTheLandmarkToFaceLies) {
  const CostMap m = open_map();
  PathGuidance g = guidance();
  Subgoal goal;
  goal.goal_W = Vec2(4.0, 0.0);
  goal.face_W = Vec2(4.0, 3.0);  // north of the destination
  // Arriving eastward: the landmark is on the left.
  const GuidanceCommand c = g.update(planar_estimate({3.8, 0.0}, 0.0, 0.01, 0.001), m, nullptr, goal);
  ASSERT_EQ(c.action, GuidanceAction::kArrived);
  ASSERT_TRUE(c.heading_rad);
  EXPECT_NEAR(*c.heading_rad, std::atan2(3.0, 0.2), 1e-9);
  // Facing west, it is on the right; no landmark, no direction.
  EXPECT_NEAR(*g.update(planar_estimate({4.0, 0.2}, kPi, 0.01, 0.001), m, nullptr, goal).heading_rad, -kPi / 2, 1e-9);
  goal.face_W.reset();
  EXPECT_FALSE(g.update(planar_estimate({4.0, 0.2}, kPi, 0.01, 0.001), m, nullptr, goal).heading_rad);
}

TEST(PathGuidance, LocatingWithholdsTheDirection) {
  const CostMap m = open_map();
  PathGuidance g = guidance();
  Subgoal goal;
  goal.direction_rad = 0.0;
  StateEstimate e = planar_estimate({0.0, 0.0}, 0.0, 0.01, 0.001);
  e.mode = EstimatorMode::kInitializing;
  GuidanceCommand c = g.update(e, m, nullptr, goal);
  EXPECT_EQ(c.action, GuidanceAction::kWait);
  EXPECT_EQ(c.reason, GuidanceReason::kLocating);
  EXPECT_FALSE(c.heading_rad.has_value());
  // Heading sigma just under and just over the 15 degree limit.
  PathGuidance direction = guidance("direction-astar");
  c = direction.update(planar_estimate({0.0, 0.0}, 0.0, 0.01, deg_to_rad(14.0)), m, nullptr, goal);
  EXPECT_EQ(c.action, GuidanceAction::kGo);
  EXPECT_LT(c.confidence, 0.1);  // sure of the way, barely sure of the heading
  c = direction.update(planar_estimate({0.0, 0.0}, 0.0, 0.01, deg_to_rad(16.0)), m, nullptr, goal);
  EXPECT_EQ(c.action, GuidanceAction::kWait);
  EXPECT_EQ(c.reason, GuidanceReason::kLocating);
  EXPECT_FALSE(c.heading_rad.has_value());
  EXPECT_NE(c.detail.find("heading sigma 16.0 deg"), std::string::npos);
  EXPECT_EQ(direction.stats().locating, 1U);
}

TEST(PathGuidance, RouteSubgoalsWaitForTheRegistration) {
  const CostMap m = open_map();
  PathGuidance g = guidance("direction-astar");
  Subgoal route;
  route.direction_rad = 0.3;
  route.from_route = true;
  StateEstimate e = planar_estimate({0.0, 0.0}, 0.0, 0.01, 0.001);
  EXPECT_EQ(g.update(e, m, nullptr, route).reason, GuidanceReason::kRegistrationUncertain);
  e.T_ENU_W = SE3();
  e.T_ENU_W_covariance = Mat4::Identity() * 0.01;
  e.T_ENU_W_covariance->operator()(0, 0) = std::pow(deg_to_rad(20.0), 2);
  const GuidanceCommand unsure = g.update(e, m, nullptr, route);
  EXPECT_EQ(unsure.action, GuidanceAction::kWait);
  EXPECT_EQ(unsure.reason, GuidanceReason::kRegistrationUncertain);
  e.T_ENU_W_covariance->operator()(0, 0) = std::pow(deg_to_rad(3.0), 2);
  EXPECT_EQ(g.update(e, m, nullptr, route).action, GuidanceAction::kGo);
}

TEST(PathGuidance, PositionSigmaLowersConfidenceAndWidensTheBerth) {
  CostMap m = open_map();
  for (int y = 40; y < 60; ++y) m.at(70, y) = 1.0F;  // a wall east of the user
  Config config = Config::parse("planning:\n  grid:\n    base_clearance_m: 0.3\n    clearance_k_sigma: 2.0\n");
  PathGuidanceConfig gc;
  gc.scope = mapping::UncertaintyScope::kAbsolute;
  Subgoal goal;
  goal.goal_W = Vec2(4.0, 0.05);
  const auto run = [&](double sigma) {
    PathGuidance g(gc, make_local_planner("astar", config));
    const GuidanceCommand c = g.update(planar_estimate({0.05, 0.05}, 0.0, sigma, 0.001), m, nullptr, goal);
    double closest = 1e9;
    for (const Vec2& q : g.plan()->path_W) closest = std::min(closest, std::abs(q.x() - 2.05) + (std::abs(q.y()) < 1.0 ? 0.0 : std::abs(std::abs(q.y()) - 1.0)));
    return std::make_pair(c, closest);
  };
  const auto [sure, sure_gap] = run(0.02);
  const auto [unsure, unsure_gap] = run(0.3);
  ASSERT_EQ(sure.action, GuidanceAction::kGo);
  ASSERT_EQ(unsure.action, GuidanceAction::kGo);
  EXPECT_GT(sure.confidence, unsure.confidence + 0.2);
  EXPECT_GT(unsure_gap, sure_gap + 0.3);
}

TEST(PathGuidance, ReplansWhenTheMapBlocksThePathOrTheSubgoalTurns) {
  CostMap m = open_map();
  PathGuidanceConfig config;
  config.replan_period_s = 100.0;
  PathGuidance g = guidance("direction-astar", config);
  Subgoal goal;
  goal.direction_rad = 0.0;
  g.update(planar_estimate({0.0, 0.0}, 0.0, 0.01, 0.001, 0), m, nullptr, goal);
  g.update(planar_estimate({0.1, 0.0}, 0.0, 0.01, 0.001, 100'000'000), m, nullptr, goal);
  EXPECT_EQ(g.stats().plans, 1U);  // nothing changed
  for (int y = 30; y < 70; ++y) m.at(75, y) = 1.0F;  // a new obstacle across the old path
  const GuidanceCommand around = g.update(planar_estimate({0.2, 0.0}, 0.0, 0.01, 0.001, 200'000'000), m, nullptr, goal);
  EXPECT_EQ(g.stats().plans, 2U);
  EXPECT_EQ(around.action, GuidanceAction::kGo);
  goal.direction_rad = kPi / 2;  // the subgoal turns north
  const GuidanceCommand north = g.update(planar_estimate({0.2, 0.0}, 0.0, 0.01, 0.001, 300'000'000), m, nullptr, goal);
  EXPECT_EQ(g.stats().plans, 3U);
  EXPECT_GT(*north.heading_rad, kPi / 4);
}

TEST(PathGuidance, TurnsBackWhenTheSubgoalSideIsWalledOffAndStopsWhenEnclosed) {
  CostMap m = open_map();
  for (int y = 0; y < 100; ++y)
    for (int x = 52; x < 56; ++x) m.at(x, y) = 1.0F;  // a wall from x = 0.2 m across the whole map
  PathGuidance g = guidance("direction-astar");
  Subgoal goal;
  goal.direction_rad = 0.0;
  const GuidanceCommand c = g.update(planar_estimate({0.05, 0.05}, 0.0, 0.01, 0.001), m, nullptr, goal);
  // The only way is back west; Direction A* still finds it (the term penalises, not forbids).
  ASSERT_EQ(c.action, GuidanceAction::kGo);
  EXPECT_GT(std::abs(*c.heading_rad), kPi / 2);
  // Walled in on every side: stop, with the planner's reason and no direction.
  for (int i = 40; i < 52; ++i) m.at(i, 45) = m.at(i, 55) = 1.0F;
  for (int y = 45; y < 56; ++y) m.at(40, y) = 1.0F;
  PathGuidance enclosed = guidance("direction-astar");
  const GuidanceCommand stop = enclosed.update(planar_estimate({0.05, 0.05}, 0.0, 0.01, 0.001), m, nullptr, goal);
  EXPECT_EQ(stop.action, GuidanceAction::kStop);
  EXPECT_EQ(stop.reason, GuidanceReason::kNoPath);
  EXPECT_FALSE(stop.heading_rad.has_value());
  EXPECT_EQ(enclosed.stats().plans_failed, 1U);
}

}  // namespace
}  // namespace navaid::planning
