// The Smart Cane loop closed with a simulated user: WPG re-plans at 10 Hz inside the sensing
// range, the PI controller (eq. 1) steers, the user turns as the cane pulls and walks on. The
// user reaches the goal round an obstacle without touching it; while locating there is no pull.
#include <gtest/gtest.h>

#include <cmath>

#include "navaid/planning/angles.hpp"
#include "navaid/planning/smart_cane_guidance.hpp"
#include "planar_estimate.hpp"

namespace navaid::planning {
namespace {

using mapping::Cell2;
using mapping::CostMap;
using mapping::GridGeometry;

// 16 x 8 m room, a 1 x 3 m block in the middle of the straight line from start to goal.
CostMap hall() {
  CostMap m(GridGeometry(Cell2(0, 0), 160, 80, 0.1), 0.9, 0.0);
  for (int x = 0; x < 160; ++x) m.at(x, 0) = m.at(x, 79) = 1.0F;
  for (int y = 0; y < 80; ++y) m.at(0, y) = m.at(159, y) = 1.0F;
  for (int x = 75; x < 85; ++x)
    for (int y = 25; y < 55; ++y) m.at(x, y) = 1.0F;
  return m;
}

// The hall, its ESDF and a cane with the default loop (uncertainty gated on absolute sigmas).
struct HallCane {
  CostMap m = hall();
  mapping::Esdf2d esdf;
  SmartCaneGuidanceConfig config = SmartCaneGuidance::default_config();
  std::unique_ptr<SmartCaneGuidance> cane;
  HallCane() {
    esdf.update(m);
    config.guidance.scope = mapping::UncertaintyScope::kAbsolute;
    cane = std::make_unique<SmartCaneGuidance>(config);
  }
};

TEST(SmartCaneGuidance, TheUserIsSteeredRoundTheBlockToTheGoal) {
  HallCane h;
  const CostMap& m = h.m;
  const mapping::Esdf2d& esdf = h.esdf;
  const SmartCaneGuidanceConfig& config = h.config;
  SmartCaneGuidance& cane = *h.cane;
  Subgoal goal;
  goal.goal_W = Vec2(14.0, 4.0);
  Vec2 p(2.0, 4.0);
  double yaw = 0.0;
  const double dt = 0.1;
  double min_clearance = 1e9;
  bool arrived = false;
  double max_steer = 0.0;
  int steps = 0;
  for (; steps < 400 && !arrived; ++steps) {
    const GuidanceCommand c = cane.update(planar_estimate(p, yaw, 0.01, 0.01, seconds_to_ns(dt * steps)), m, esdf, goal);
    if (c.action == GuidanceAction::kArrived) {
      arrived = true;
      break;
    }
    ASSERT_EQ(c.action, GuidanceAction::kGo) << c.detail << " at " << p.transpose();
    ASSERT_TRUE(c.steering_rad.has_value());
    max_steer = std::max(max_steer, std::abs(*c.steering_rad));
    // The cane's motor turns the user: yaw rate 3 x v [rad/s]; the user walks 1 m/s.
    yaw = wrap_angle(yaw + dt * 3.0 * *c.steering_rad);
    p += dt * 1.0 * Vec2(std::cos(yaw), std::sin(yaw));
    min_clearance = std::min(min_clearance, *esdf.distance(p));
  }
  EXPECT_TRUE(arrived) << "at " << p.transpose() << " after " << steps << " steps";
  EXPECT_GT(min_clearance, 0.2);  // never closer than 0.2 m to the block or the walls
  EXPECT_GT(max_steer, 0.05);     // it did steer
  EXPECT_LE(max_steer, config.pi.output_limit + 1e-12);
  // 10 Hz: about one plan per cycle.
  EXPECT_GE(cane.chain().stats().plans, static_cast<std::size_t>(steps * 0.9));
}

TEST(SmartCaneGuidance, NoPullWhileLocating) {
  HallCane h;
  const CostMap& m = h.m;
  const mapping::Esdf2d& esdf = h.esdf;
  SmartCaneGuidance& cane = *h.cane;
  Subgoal goal;
  goal.goal_W = Vec2(14.0, 6.5);
  const GuidanceCommand go = cane.update(planar_estimate({2.0, 4.0}, 0.0, 0.01, 0.01, 0), m, esdf, goal);
  ASSERT_EQ(go.action, GuidanceAction::kGo);
  EXPECT_NE(*go.steering_rad, 0.0);
  const GuidanceCommand lost = cane.update(planar_estimate({2.0, 4.0}, 0.0, 0.01, deg_to_rad(30.0), seconds_to_ns(0.1)), m, esdf, goal);
  EXPECT_EQ(lost.action, GuidanceAction::kWait);
  EXPECT_EQ(lost.reason, GuidanceReason::kLocating);
  EXPECT_FALSE(lost.heading_rad.has_value());
  EXPECT_DOUBLE_EQ(*lost.steering_rad, 0.0);
}

TEST(SmartCaneGuidance, KeysKeepThe10HzAnd10mDefaults) {
  const SmartCaneGuidanceConfig d = read_smart_cane_guidance_config(Config::parse("{}", "<t>", {}));
  EXPECT_DOUBLE_EQ(d.guidance.replan_period_s, 0.1);
  EXPECT_DOUBLE_EQ(d.wpg.horizon_m, 10.0);
  const SmartCaneGuidanceConfig c = read_smart_cane_guidance_config(
      Config::parse("{}", "<t>", {"planning.wpg.horizon_m=6", "planning.pi.kp=0.3", "planning.guidance.replan_period_s=0.2"}));
  EXPECT_DOUBLE_EQ(c.wpg.horizon_m, 6.0);
  EXPECT_DOUBLE_EQ(c.pi.kp, 0.3);
  EXPECT_DOUBLE_EQ(c.guidance.replan_period_s, 0.2);
}

}  // namespace
}  // namespace navaid::planning
