// The walking-path generator (Smart Cane Alg. 1, eq. 9-10): edge costs with known answers, paths
// whose every CoM sample and gait point clear the obstacles, the coarse-grid heuristic, clear
// reasons for every way a plan cannot start or finish, limits, directional subgoals inside the
// re-planning horizon, and clearance that grows with the estimate's sigma.
#include <gtest/gtest.h>

#include <cmath>

#include "navaid/core/errors.hpp"
#include "navaid/planning/angles.hpp"
#include "navaid/planning/grid_astar.hpp"
#include "navaid/planning/grid_distance_heuristic.hpp"
#include "navaid/planning/wpg_planner.hpp"

namespace navaid::planning {
namespace {

using mapping::Cell2;
using mapping::CostMap;
using mapping::GridGeometry;

// A w x h m room at 0.1 m with a wall around it.
CostMap room(double w_m, double h_m) {
  const int w = static_cast<int>(std::lround(w_m / 0.1));
  const int h = static_cast<int>(std::lround(h_m / 0.1));
  CostMap m(GridGeometry(Cell2(0, 0), w, h, 0.1), 0.9, 0.0);
  for (int x = 0; x < w; ++x) m.at(x, 0) = m.at(x, h - 1) = 1.0F;
  for (int y = 0; y < h; ++y) m.at(0, y) = m.at(w - 1, y) = 1.0F;
  return m;
}

// A wall at x = x_m (one cell thick) from y0 to y1.
void wall_x(CostMap& m, double x_m, double y0_m, double y1_m) {
  const int x = static_cast<int>(x_m / 0.1);
  for (int y = static_cast<int>(y0_m / 0.1); y < static_cast<int>(y1_m / 0.1); ++y) m.at(x, y) = 1.0F;
}

struct Planned {
  Plan plan;
  mapping::Esdf2d esdf;
};

Plan plan_on(const CostMap& m, const mapping::Esdf2d& esdf, PlanarPose start, std::optional<Vec2> goal,
             const WpgConfig& c = {}, double sigma = 0.0, std::optional<double> direction = std::nullopt) {
  PlanningProblem p;
  p.cost = &m;
  p.esdf = &esdf;
  p.start = start;
  p.goal_W = goal;
  p.goal_direction_rad = direction;
  p.sigma_xy_m = sigma;
  return WpgPlanner(c).plan(p);
}

mapping::Esdf2d esdf_of(const CostMap& m) {
  mapping::Esdf2d e;
  e.update(m);
  return e;
}

// Every CoM touchdown and gait point of the plan clears the obstacles by its sphere.
void expect_clear(const Plan& p, const mapping::Esdf2d& esdf, const WpgConfig& c, double margin = 0.0) {
  ASSERT_EQ(p.path_W.size(), p.footsteps_W.size());
  ASSERT_EQ(p.path_W.size(), p.yaw_rad.size());
  for (std::size_t i = 0; i < p.path_W.size(); ++i) {
    EXPECT_GE(*esdf.distance(p.path_W[i]), c.com_radius_m + margin - 1e-9) << i;
    EXPECT_GE(*esdf.distance(p.footsteps_W[i]), c.foot_radius_m + margin - 1e-9) << i;
  }
}

TEST(WpgCost, Equations9And10) {
  WpgConfig c;
  c.turn_weight = 0.5;
  c.risk_weight = 2.0;
  c.risk_distance_m = 0.6;
  // D + sigma |theta| + w_o (d_max - d): 0.5 + 0.5 x 0.5236 + 2 x (0.6 - 0.4).
  EXPECT_NEAR(wpg_edge_cost(c, 0.5, 0.5235987756, 0.4), 0.5 + 0.2617993878 + 0.4, 1e-12);
  EXPECT_NEAR(wpg_edge_cost(c, 0.5, -0.5235987756, 0.4), 0.5 + 0.2617993878 + 0.4, 1e-12);  // |theta|
  EXPECT_NEAR(wpg_edge_cost(c, 0.5, 0.0, 0.6), 0.5, 1e-12);   // at d_max: no risk
  EXPECT_NEAR(wpg_edge_cost(c, 0.5, 0.0, 3.0), 0.5, 1e-12);   // beyond: none (the 0 branch of eq. 10)
}

TEST(WpgInputs, ThePapersRangesOnAGrid) {
  WpgConfig c;  // a_l in {0.4, 0.5, 0.6}, a_w = 0.15, dtheta in {0, +-15, +-30} deg
  const std::vector<LfpcInput> in = wpg_inputs(c);
  ASSERT_EQ(in.size(), 15U);
  double max_turn = 0.0;
  for (const LfpcInput& u : in) {
    EXPECT_GE(u.step_length_m, 0.4 - 1e-12);
    EXPECT_LE(u.step_length_m, 0.6 + 1e-12);
    EXPECT_NEAR(u.step_width_m, 0.15, 1e-12);
    max_turn = std::max(max_turn, std::abs(u.direction_rad));
  }
  EXPECT_NEAR(max_turn, 30.0 * 3.14159265358979323846 / 180.0, 1e-9);
  c.step_widths = 2;
  c.turns_per_side = 3;
  EXPECT_EQ(wpg_inputs(c).size(), 3U * 2U * 7U);
}

TEST(WpgPlanner, StraightAcrossAnEmptyRoom) {
  const CostMap m = room(12.0, 6.0);
  const mapping::Esdf2d esdf = esdf_of(m);
  const WpgConfig c;
  const Plan p = plan_on(m, esdf, PlanarPose{Vec2(1.5, 3.0), 0.0}, Vec2(10.5, 3.0), c);
  ASSERT_TRUE(p.found()) << p.detail;
  EXPECT_EQ(p.reason, GuidanceReason::kPathFound);
  EXPECT_LE((p.path_W.back() - Vec2(10.5, 3.0)).norm(), c.goal_tolerance_m + 1e-9);
  EXPECT_GT(p.length_m, 8.4);
  EXPECT_LT(p.length_m, 9.6);
  // Footsteps of 0.4-0.6 m: about 9 m / 0.5 m of them, none turning much on a straight walk.
  EXPECT_GE(p.path_W.size(), 12U);
  EXPECT_LE(p.path_W.size(), 30U);
  for (const double yaw : p.yaw_rad) EXPECT_LT(std::abs(yaw), 0.6);
  expect_clear(p, esdf, c);
  EXPECT_GT(p.expanded, 0U);
  EXPECT_GE(p.cost, p.length_m - 1e-9);  // eq. 9's distance term alone is the length
}

TEST(WpgPlanner, ThroughTheDoorOfAWallAndDeterministic) {
  CostMap m = room(12.0, 8.0);
  wall_x(m, 6.0, 0.0, 5.5);  // a door from 5.5 to 7.9 m at the top
  const mapping::Esdf2d esdf = esdf_of(m);
  const WpgConfig c;
  const Plan p = plan_on(m, esdf, PlanarPose{Vec2(2.0, 2.0), 0.0}, Vec2(10.0, 2.0), c);
  ASSERT_TRUE(p.found()) << p.detail;
  expect_clear(p, esdf, c);
  double top = 0.0;
  for (const Vec2& q : p.path_W) top = std::max(top, q.y());
  EXPECT_GT(top, 5.5 + c.com_radius_m - 1e-9);  // it went through the door
  EXPECT_GT(p.length_m, 11.0);  // around the wall (2 x 5.5 m up to the door and down), not through it
  const Plan again = plan_on(m, esdf, PlanarPose{Vec2(2.0, 2.0), 0.0}, Vec2(10.0, 2.0), c);
  ASSERT_EQ(again.path_W.size(), p.path_W.size());
  for (std::size_t i = 0; i < p.path_W.size(); ++i) EXPECT_EQ(again.path_W[i], p.path_W[i]);
  EXPECT_EQ(again.expanded, p.expanded);
}

TEST(WpgPlanner, TheStartHeadingCostsATurnOnTheSpot) {
  const CostMap m = room(12.0, 6.0);
  const mapping::Esdf2d esdf = esdf_of(m);
  const Plan ahead = plan_on(m, esdf, PlanarPose{Vec2(3.0, 3.0), 0.0}, Vec2(10.0, 3.0));
  const Plan behind = plan_on(m, esdf, PlanarPose{Vec2(3.0, 3.0), 3.14159265358979323846}, Vec2(10.0, 3.0));
  ASSERT_TRUE(ahead.found());
  ASSERT_TRUE(behind.found());  // the user turns round before the first step
  EXPECT_GT(behind.cost, ahead.cost + 0.5 * 3.0);  // sigma x pi (the turn), nearly
  EXPECT_LT(std::abs(behind.yaw_rad[1]), 0.53);    // the first step already heads to the goal (+-30 deg)
}

TEST(WpgPlanner, ReasonsForNoPlan) {
  CostMap m = room(10.0, 6.0);
  wall_x(m, 5.0, 0.0, 6.0);  // splits the room
  const mapping::Esdf2d esdf = esdf_of(m);
  const Plan none = plan_on(m, esdf, PlanarPose{Vec2(2.0, 3.0), 0.0}, Vec2(8.0, 3.0));
  EXPECT_FALSE(none.found());
  EXPECT_EQ(none.reason, GuidanceReason::kNoPath);
  EXPECT_NE(none.detail.find("no path"), std::string::npos);

  const Plan in_wall = plan_on(m, esdf, PlanarPose{Vec2(5.05, 3.0), 0.0}, Vec2(8.0, 3.0));
  EXPECT_EQ(in_wall.reason, GuidanceReason::kStartBlocked);
  EXPECT_NE(in_wall.detail.find("lies in an obstacle"), std::string::npos);
  const Plan too_close = plan_on(m, esdf, PlanarPose{Vec2(2.0, 3.0), 0.0}, Vec2(4.8, 3.0));
  EXPECT_EQ(too_close.reason, GuidanceReason::kGoalBlocked);
  EXPECT_NE(too_close.detail.find("body sphere"), std::string::npos);
  const Plan off = plan_on(m, esdf, PlanarPose{Vec2(2.0, 3.0), 0.0}, Vec2(30.0, 3.0));
  EXPECT_EQ(off.reason, GuidanceReason::kOffMap);

  WpgConfig limited;
  limited.limits.max_expansions = 5;
  const Plan cut = plan_on(m, esdf, PlanarPose{Vec2(2.0, 3.0), 0.0}, Vec2(4.0, 1.0), limited);
  EXPECT_EQ(cut.reason, GuidanceReason::kSearchLimit);
  EXPECT_EQ(cut.expanded, 5U);
}

TEST(WpgPlanner, ProblemsItCannotTakeAreErrors) {
  const CostMap m = room(10.0, 6.0);
  PlanningProblem p;
  p.cost = &m;
  p.start = PlanarPose{Vec2(2.0, 3.0), 0.0};
  p.goal_W = Vec2(8.0, 3.0);
  EXPECT_THROW(WpgPlanner().plan(p), Error);  // no ESDF
  const mapping::Esdf2d esdf = esdf_of(m);
  p.esdf = &esdf;
  p.goal_W.reset();
  p.goal_direction_rad = 0.0;
  EXPECT_THROW(WpgPlanner().plan(p), Error);  // a direction needs a horizon
  p.goal_direction_rad.reset();
  EXPECT_THROW(WpgPlanner().plan(p), Error);  // no goal at all
}

TEST(WpgPlanner, ClearanceGrowsWithTheEstimatesSigma) {
  CostMap m = room(12.0, 6.0);
  wall_x(m, 6.0, 0.0, 2.4);
  wall_x(m, 6.0, 3.6, 6.0);  // a 1.2 m gap between cell faces, 1.3 m between the cell centres the ESDF sees
  const mapping::Esdf2d esdf = esdf_of(m);
  const WpgConfig c;
  const Plan sure = plan_on(m, esdf, PlanarPose{Vec2(2.0, 3.0), 0.0}, Vec2(10.0, 3.0), c, 0.0);
  ASSERT_TRUE(sure.found()) << sure.detail;
  expect_clear(sure, esdf, c);
  const Plan unsure = plan_on(m, esdf, PlanarPose{Vec2(2.0, 3.0), 0.0}, Vec2(10.0, 3.0), c, 0.4);
  EXPECT_FALSE(unsure.found());  // 0.3 + 0.4 m each side needs 1.4 m
  EXPECT_EQ(unsure.reason, GuidanceReason::kNoPath);
}

TEST(WpgCost, TraversalTermChargesTheCellCostPerMetre) {
  WpgConfig c;
  EXPECT_DOUBLE_EQ(wpg_edge_cost(c, 0.5, 0.0, 2.0, 0.5), 0.5);  // weight 0: eq. 9-10 alone
  c.traversal_weight = 2.0;
  EXPECT_DOUBLE_EQ(wpg_edge_cost(c, 0.5, 0.0, 2.0, 0.5), 0.5 + 2.0 * 0.5 * 0.5);
  EXPECT_DOUBLE_EQ(wpg_edge_cost(c, 0.5, 0.0, 2.0, 0.0), 0.5);  // seen free ground costs nothing more
}

TEST(WpgPlanner, TraversalWeightKeepsThePathOnSeenGround) {
  // An open room whose lower half is seen free (cost 0) and upper half unseen (0.5), a goal on the
  // boundary: with the weight the path stays below, on seen ground; without it, either half will do.
  CostMap m = room(12.0, 8.0);
  for (int x = 1; x < 119; ++x)
    for (int y = 40; y < 79; ++y) m.at(x, y) = 0.5F;
  const mapping::Esdf2d esdf = esdf_of(m);
  WpgConfig c;
  c.traversal_weight = 2.0;
  // Start and goal just above the boundary: the straight way lies in unseen cells.
  const Plan p = plan_on(m, esdf, PlanarPose{Vec2(1.5, 4.2), 0.0}, Vec2(10.5, 4.2), c);
  ASSERT_TRUE(p.found()) << p.detail;
  std::size_t unseen = 0;
  for (const Vec2& q : p.path_W) unseen += q.y() >= 4.0 ? 1 : 0;
  EXPECT_LE(unseen, 4U);  // the first steps and the arrival only
  const Plan plain = plan_on(m, esdf, PlanarPose{Vec2(1.5, 4.2), 0.0}, Vec2(10.5, 4.2));
  ASSERT_TRUE(plain.found());
  std::size_t plain_unseen = 0;
  for (const Vec2& q : plain.path_W) plain_unseen += q.y() >= 4.0 ? 1 : 0;
  EXPECT_GT(plain_unseen, unseen + 5);
  EXPECT_GT(p.cost, p.length_m);  // the unseen steps are charged
}

TEST(WpgPlanner, AWalkInProgressGoesOnInsteadOfTurningOnTheSpot) {
  const CostMap m = room(12.0, 8.0);
  const mapping::Esdf2d esdf = esdf_of(m);
  const WpgConfig c;
  PlanningProblem p;
  p.cost = &m;
  p.esdf = &esdf;
  p.start = PlanarPose{Vec2(5.0, 4.0), 0.0};
  p.goal_W = Vec2(2.0, 4.0);  // behind the user
  const Plan standing = WpgPlanner(c).plan(p);
  ASSERT_TRUE(standing.found());
  EXPECT_GT(std::abs(wrap_angle(standing.yaw_rad[1])), 2.5);  // turns round on the spot
  p.start_speed_mps = 1.0;
  const Plan walking = WpgPlanner(c).plan(p);
  ASSERT_TRUE(walking.found()) << walking.detail;
  for (std::size_t i = 1; i < walking.yaw_rad.size(); ++i)  // a U-turn in steps of at most 30 deg
    EXPECT_LE(std::abs(wrap_angle(walking.yaw_rad[i] - walking.yaw_rad[i - 1])), c.max_turn_rad + 1e-9) << i;
  EXPECT_GT(walking.length_m, standing.length_m);
  // Walking at a wall with no room to turn: it stops and turns on the spot instead of giving up.
  p.start = PlanarPose{Vec2(11.0, 4.0), 0.0};
  p.goal_W = Vec2(8.0, 4.0);
  const Plan cornered = WpgPlanner(c).plan(p);
  ASSERT_TRUE(cornered.found()) << cornered.detail;
  EXPECT_GT(std::abs(wrap_angle(cornered.yaw_rad[1])), 2.5);
}

TEST(WpgPlanner, EscapeLeadsAUserStandingTooNearAWallAwayFromIt) {
  const CostMap m = room(12.0, 6.0);
  const mapping::Esdf2d esdf = esdf_of(m);
  const PlanarPose against_wall{Vec2(3.0, 0.25), 0.0};  // 0.15 m from the wall cell's centre
  WpgConfig c;
  const Plan stuck = plan_on(m, esdf, against_wall, Vec2(10.0, 3.0), c);
  EXPECT_EQ(stuck.reason, GuidanceReason::kStartBlocked);  // the paper's CheckSafe
  c.escape_distance_m = 1.0;
  const Plan away = plan_on(m, esdf, against_wall, Vec2(10.0, 3.0), c);
  ASSERT_TRUE(away.found()) << away.detail;
  // Within 1 m of the start the CoM keeps at least the start's clearance; beyond it the full sphere.
  const double d0 = *esdf.distance(against_wall.position);
  for (const Vec2& q : away.path_W) {
    const bool near = (q - against_wall.position).norm() < 1.0;
    EXPECT_GE(*esdf.distance(q), (near ? d0 : c.com_radius_m) - 1e-6);
  }
  // Standing along the wall, the goal across the room: from rest the push-off foot lands behind the
  // CoM, in the wall; the escape leaves the gait points unchecked near the start.
  const Plan across = plan_on(m, esdf, against_wall, Vec2(3.0, 5.0), c);
  ASSERT_TRUE(across.found()) << across.detail;
  EXPECT_GE(*esdf.distance(across.path_W.back()), c.com_radius_m - 1e-9);  // the full sphere at the end
  // The trial's case: stopped 0.1 m before an obstacle, 0.4 m from the wall behind the right
  // shoulder, the way round on the left. From rest the push-off foot lands behind the CoM, in the
  // wall, for every turn to the left; the escape leaves the gait points unchecked near the start.
  CostMap corridor = room(12.0, 3.0);
  for (int x = 46; x < 53; ++x)
    for (int y = 1; y < 9; ++y) corridor.at(x, y) = 1.0F;
  const mapping::Esdf2d corridor_esdf = esdf_of(corridor);
  const Plan around = plan_on(corridor, corridor_esdf, PlanarPose{Vec2(4.45, 0.45), 0.0}, Vec2(10.0, 1.5), c);
  ASSERT_TRUE(around.found()) << around.detail;
  double left_most = 0.0;
  for (const Vec2& q : around.path_W) left_most = std::max(left_most, q.y());
  EXPECT_GT(left_most, 0.9 + c.com_radius_m);  // round the obstacle on the left
  // Standing in the wall stays blocked.
  const Plan in_wall = plan_on(m, esdf, PlanarPose{Vec2(3.0, 0.05), 0.0}, Vec2(10.0, 3.0), c);
  EXPECT_EQ(in_wall.reason, GuidanceReason::kStartBlocked);
}

TEST(WpgPlanner, DirectionalSubgoalInsideTheHorizon) {
  const CostMap m = room(20.0, 20.0);
  const mapping::Esdf2d esdf = esdf_of(m);
  WpgConfig c;
  c.horizon_m = 5.0;
  const double up = 3.14159265358979323846 / 2.0;
  const Plan p = plan_on(m, esdf, PlanarPose{Vec2(10.0, 5.0), up}, std::nullopt, c, 0.0, up);
  ASSERT_TRUE(p.found()) << p.detail;
  const Vec2 end = p.path_W.back() - Vec2(10.0, 5.0);
  EXPECT_GE(end.norm(), 5.0);
  EXPECT_LT(end.norm(), 5.8);
  EXPECT_LT(std::abs(std::atan2(end.y(), end.x()) - up), 0.1);
  // Facing away, the plan trades the turn on the spot (sigma |turn|) against beta (1 - cos): it
  // still ends on the subgoal's side.
  const Plan turned = plan_on(m, esdf, PlanarPose{Vec2(10.0, 5.0), 0.0}, std::nullopt, c, 0.0, up);
  ASSERT_TRUE(turned.found());
  const Vec2 e2 = turned.path_W.back() - Vec2(10.0, 5.0);
  EXPECT_LT(std::abs(std::atan2(e2.y(), e2.x()) - up), 0.5);
  // A point goal beyond the horizon: the plan stops at the horizon, headed for the goal.
  const Plan far = plan_on(m, esdf, PlanarPose{Vec2(3.0, 3.0), 0.0}, Vec2(17.0, 17.0), c);
  ASSERT_TRUE(far.found());
  EXPECT_GE((far.path_W.back() - Vec2(3.0, 3.0)).norm(), 5.0);
  EXPECT_LT((far.path_W.back() - Vec2(17.0, 17.0)).norm(), (Vec2(17.0, 17.0) - Vec2(3.0, 3.0)).norm() - 4.5);
}

TEST(WpgPlanner, FactoryAndKeys) {
  const std::unique_ptr<LocalPlanner> p = make_local_planner("wpg", Config::parse("{}", "<t>", {}));
  EXPECT_EQ(p->name(), "wpg");
  const Config cfg = Config::parse("{}", "<t>",
                                   {"planning.wpg.step_length_m=[0.45, 0.55]", "planning.wpg.turns_per_side=3",
                                    "planning.wpg.max_turn_deg=20", "planning.wpg.horizon_m=10"});
  const WpgConfig c = read_wpg_config(cfg);
  EXPECT_DOUBLE_EQ(c.step_length_min_m, 0.45);
  EXPECT_DOUBLE_EQ(c.step_length_max_m, 0.55);
  EXPECT_EQ(c.turns_per_side, 3);
  EXPECT_NEAR(c.max_turn_rad, 20.0 * 3.14159265358979323846 / 180.0, 1e-12);
  EXPECT_DOUBLE_EQ(c.horizon_m, 10.0);
  // b outside eq. 8's interval for the model is refused with the interval.
  try {
    read_wpg_config(Config::parse("{}", "<t>", {"planning.wpg.lfpc_gain=0.05"}));
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("0.140 < b < 0.716"), std::string::npos) << e.what();
  }
  EXPECT_THROW(read_wpg_config(Config::parse("{}", "<t>", {"planning.wpg.step_length_m=[0.6, 0.4]"})), ConfigError);
  EXPECT_THROW(read_wpg_config(Config::parse("{}", "<t>", {"planning.wpg.heuristic=magic"})), ConfigError);
}

TEST(GridDistanceHeuristic, SeesWallsAndDoorsThatTheStraightDistanceDoesNot) {
  CostMap m = room(12.0, 8.0);
  wall_x(m, 6.0, 0.0, 5.5);  // door at the top, 5.5-7.9 m
  const mapping::Esdf2d esdf = esdf_of(m);
  const Vec2 goal(10.0, 2.0);
  const Vec2 start(2.0, 2.0);
  GridDistanceHeuristic h(esdf, goal, start, 0.5, 0.3);
  const double at_start = h.at(start);
  // The walk goes up to the door and down again (about 2 x 5.5 m); the straight line is 8 m.
  GridAStarConfig ac;
  ac.cost.base_clearance_m = 0.3;
  PlanningProblem p;
  p.cost = &m;
  p.esdf = &esdf;
  p.start = PlanarPose{start, 0.0};
  p.goal_W = goal;
  const Plan astar = GridAStarPlanner(ac).plan(p);
  ASSERT_TRUE(astar.found());
  EXPECT_GT(at_start, 9.5);
  EXPECT_LT(at_start, astar.length_m + 0.5);
  EXPECT_NEAR(h.at(goal), 0.0, 1e-12);
  EXPECT_GE(h.at(Vec2(9.0, 6.0)), (Vec2(9.0, 6.0) - goal).norm());  // never below the straight distance
  EXPECT_TRUE(std::isinf(h.at(Vec2(50.0, 2.0))));                     // off the map
  // Only what the queries needed was settled, not the whole room.
  EXPECT_LT(h.settled(), static_cast<std::size_t>(24 * 16));
}

TEST(GridDistanceHeuristic, AClosedWallLeavesNoWay) {
  CostMap m = room(10.0, 6.0);
  wall_x(m, 5.0, 0.0, 6.0);
  const mapping::Esdf2d esdf = esdf_of(m);
  GridDistanceHeuristic h(esdf, Vec2(8.0, 3.0), Vec2(2.0, 3.0), 0.5, 0.3);
  EXPECT_TRUE(std::isinf(h.at(Vec2(2.0, 3.0))));
  EXPECT_TRUE(std::isfinite(h.at(Vec2(7.0, 3.0))));
}

}  // namespace
}  // namespace navaid::planning
