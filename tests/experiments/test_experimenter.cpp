// The trial's experimenter (eLabrador's "correction number"): intervenes when the person leaves
// the route or stands stuck, turns them toward the route ahead of them, waits before the next.
#include <gtest/gtest.h>

#include <cmath>

#include "navaid/core/errors.hpp"
#include "navaid/experiments/experimenter.hpp"

namespace navaid::experiments {
namespace {

using Vec2 = Eigen::Vector2d;

// An L: 30 m south, then 100 m east.
const std::vector<Vec2> kRoute{Vec2(0, 30), Vec2(0, 0), Vec2(100, 0)};

ExperimenterConfig config() {
  ExperimenterConfig c;
  c.off_route_m = 5.0;
  c.stuck_s = 30.0;
  c.ahead_m = 5.0;
  c.cooldown_s = 10.0;
  return c;
}

TEST(Experimenter, TurnsAPersonWhoLeftTheRouteTowardItAheadOfThem) {
  Experimenter e(config(), kRoute);
  EXPECT_FALSE(e.watch(0.0, Vec2(20, 4.9), 1.0, false));  // 4.9 m off: left alone
  const auto h = e.watch(1.0, Vec2(20, 6.0), 1.0, false);
  ASSERT_TRUE(h);
  // The nearest route point is (20, 0); 5 m ahead along the route: (25, 0).
  EXPECT_NEAR(*h, std::atan2(-6.0, 5.0), 1e-12);
  EXPECT_EQ(e.corrections(), 1u);
  EXPECT_NEAR(e.max_off_route_m(), 6.0, 1e-12);
  // Still off, but within the cooldown; after it, again.
  EXPECT_FALSE(e.watch(5.0, Vec2(20, 6.0), 1.0, false));
  EXPECT_TRUE(e.watch(11.5, Vec2(20, 6.0), 1.0, false));
  EXPECT_EQ(e.corrections(), 2u);
  // Round the corner: ahead of (0, 2) is past the turn, on the east leg.
  Experimenter corner(config(), kRoute);
  const auto c = corner.watch(0.0, Vec2(-6.0, 2.0), 1.0, false);
  ASSERT_TRUE(c);
  EXPECT_NEAR(*c, std::atan2(0.0 - 2.0, 3.0 - -6.0), 1e-12);
}

TEST(Experimenter, OneWhoStandsTooLongIsSetWalkingButNotOnceArrived) {
  Experimenter e(config(), kRoute);
  EXPECT_FALSE(e.watch(0.0, Vec2(0, 10), 0.0, false));
  EXPECT_FALSE(e.watch(29.9, Vec2(0, 10), 0.0, false));
  const auto h = e.watch(30.0, Vec2(0, 10), 0.0, false);
  ASSERT_TRUE(h);
  EXPECT_NEAR(*h, -M_PI / 2, 1e-12);  // south, along the route
  // Walking in between restarts the clock; arrived people are left alone.
  Experimenter f(config(), kRoute);
  f.watch(0.0, Vec2(0, 10), 0.0, false);
  f.watch(20.0, Vec2(0, 10), 0.5, false);
  EXPECT_FALSE(f.watch(45.0, Vec2(0, 10), 0.0, false));
  EXPECT_FALSE(f.watch(100.0, Vec2(50, 20), 0.0, true));
  EXPECT_EQ(f.corrections(), 0u);
}

TEST(Experimenter, KeysAndDefaults) {
  const Config none = Config::parse("{}", "<test>");
  EXPECT_EQ(read_experimenter_config(none, false).off_route_m, 0.0);  // not a route study: no experimenter
  EXPECT_EQ(read_experimenter_config(none, true).off_route_m, 5.0);
  EXPECT_EQ(read_experimenter_config(none, true).stuck_s, 30.0);
  EXPECT_EQ(read_experimenter_config(Config::parse("{}", "<test>", {"trial.correction.stuck_s=12"}), true).stuck_s, 12.0);
  EXPECT_THROW(read_experimenter_config(Config::parse("{}", "<test>", {"trial.correction.off_route_m=-1"}), true),
               ConfigError);
  EXPECT_THROW(Experimenter(config(), {Vec2(0, 0)}), std::invalid_argument);
}

}  // namespace
}  // namespace navaid::experiments
