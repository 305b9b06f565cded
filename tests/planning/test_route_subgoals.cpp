// Sub-routes and the eLabrador subgoal rule (nearest sub-route -> heading at the local map's edge),
// the ENU frame and the hand-over to W through the GPS-map registration.
#include <gtest/gtest.h>

#include <cmath>

#include "navaid/core/errors.hpp"
#include "navaid/planning/route_subgoals.hpp"

using namespace navaid::planning;

namespace {

constexpr double kPi = 3.14159265358979323846;
const std::vector<Vec2> kL = {Vec2(0, 0), Vec2(20, 0), Vec2(20, 20)};  // east 20 m, then north 20 m

TEST(SubRoutes, CutIntoPiecesOfTheConfiguredLength) {
  const auto s = cut_sub_routes({Vec2(0, 0), Vec2(25, 0)}, 10.0);
  ASSERT_EQ(s.size(), 3U);
  EXPECT_NEAR(s[0].end_m, 10.0, 1e-9);
  EXPECT_NEAR(s[2].end_m - s[2].start_m, 5.0, 1e-9);
  EXPECT_TRUE(s[1].points_ENU.front().isApprox(s[0].points_ENU.back()));
  const auto l = cut_sub_routes(kL, 10.0);
  ASSERT_EQ(l.size(), 4U);
  EXPECT_TRUE(l[1].points_ENU.back().isApprox(Vec2(20, 0)));
  EXPECT_TRUE(cut_sub_routes({Vec2(1, 1), Vec2(1, 1)}, 10.0).empty());
  // A sliver at the end joins the last piece.
  const auto sliver = cut_sub_routes({Vec2(0, 0), Vec2(20.05, 0)}, 10.0);
  ASSERT_EQ(sliver.size(), 2U);
  EXPECT_NEAR(sliver[1].end_m, 20.05, 1e-9);
  // A corner inside a piece keeps its vertex.
  const auto c = cut_sub_routes(kL, 15.0);
  ASSERT_EQ(c.size(), 3U);
  EXPECT_EQ(c[1].points_ENU.size(), 3U);
}

TEST(RouteSubgoal, HeadingToTheWindowEdgeAlongTheNearestSubRoute) {
  const auto s = cut_sub_routes(kL, 10.0);
  const RouteSubgoal a = route_subgoal(s, Vec2(12, 0.5), 10.0);
  EXPECT_EQ(a.subroute, 1U);
  EXPECT_NEAR(a.distance_to_route_m, 0.5, 1e-9);
  EXPECT_TRUE(a.subgoal.from_route);
  ASSERT_TRUE(a.subgoal.direction_rad);
  EXPECT_FALSE(a.subgoal.goal_W);
  EXPECT_NEAR(*a.subgoal.direction_rad, std::atan2(-0.5, std::sqrt(25.0 - 0.25)), 1e-6);
  // Near the corner the edge point lies on the northward leg.
  const RouteSubgoal b = route_subgoal(s, Vec2(19, 2), 10.0);
  EXPECT_EQ(b.subroute, 2U);
  EXPECT_NEAR(*b.subgoal.direction_rad, std::atan2(std::sqrt(24.0), 1.0), 1e-6);
  // A wider window looks further ahead.
  const RouteSubgoal w = route_subgoal(s, Vec2(12, 0), 20.0);
  EXPECT_NEAR(*w.subgoal.direction_rad, std::atan2(std::sqrt(100.0 - 64.0), 8.0), 1e-6);
}

TEST(RouteSubgoal, DestinationInsideTheWindowAndUserOffTheRoute) {
  const auto s = cut_sub_routes(kL, 10.0);
  const RouteSubgoal end = route_subgoal(s, Vec2(20, 17), 10.0);
  EXPECT_TRUE(end.reaches_destination);
  ASSERT_TRUE(end.subgoal.goal_W);
  EXPECT_TRUE(end.subgoal.goal_W->isApprox(Vec2(20, 20)));
  EXPECT_NEAR(*end.subgoal.direction_rad, kPi / 2, 1e-9);
  const RouteSubgoal off = route_subgoal(s, Vec2(40, 10), 10.0);  // 20 m east of the north leg
  EXPECT_NEAR(off.distance_to_route_m, 20.0, 1e-9);
  EXPECT_NEAR(std::abs(*off.subgoal.direction_rad), kPi, 1e-9);  // back west to the route
  EXPECT_THROW(route_subgoal({}, Vec2(0, 0), 10.0), navaid::Error);
}

TEST(RouteSubgoal, IntoTheEstimatorWorldFrame) {
  // A StateEstimate's T_ENU_W: W's x axis points north, W's origin 5 m east.
  const navaid::SE3 T_ENU_W(navaid::Quat(Eigen::AngleAxisd(kPi / 2, navaid::Vec3::UnitZ())), navaid::Vec3(5.0, 0.0, 0.0));
  Subgoal enu;
  enu.goal_W = Vec2(5, 10);
  enu.direction_rad = kPi / 2;
  enu.from_route = true;
  const Subgoal w = subgoal_in_world(enu, T_ENU_W);
  ASSERT_TRUE(w.goal_W);
  EXPECT_NEAR(w.goal_W->x(), 10.0, 1e-9);
  EXPECT_NEAR(w.goal_W->y(), 0.0, 1e-9);
  EXPECT_NEAR(*w.direction_rad, 0.0, 1e-9);  // north in ENU = +x in W
  EXPECT_TRUE(w.from_route);
  // Consistent with the transform itself.
  const navaid::Vec3 back = T_ENU_W * navaid::Vec3(w.goal_W->x(), w.goal_W->y(), 0.0);
  EXPECT_NEAR(back.x(), 5.0, 1e-9);
  EXPECT_NEAR(back.y(), 10.0, 1e-9);
}

TEST(LocalEnu, MetresAndRoundTrip) {
  const LocalEnu enu(navaid::GeodeticOrigin{48.0, 11.0, 0.0});
  const Vec2 north = enu.to_enu(GeoPoint{48.001, 11.0});
  EXPECT_NEAR(north.y(), 111.2, 0.2);  // WGS84 meridian arc, 0.001 deg at 48 N
  const Vec2 east = enu.to_enu(GeoPoint{48.0, 11.001});
  EXPECT_NEAR(east.x(), 74.6, 0.2);
  const GeoPoint p = enu.to_geo(Vec2(123.0, -45.0));
  EXPECT_TRUE(enu.to_enu(p).isApprox(Vec2(123.0, -45.0), 1e-9));
  EXPECT_NEAR(haversine_m(48.0, 11.0, 48.001, 11.001), std::hypot(111.2, 74.6), 0.5);
}

TEST(SubRouteConfig, KeysAndRanges) {
  const SubRouteConfig c = sub_route_config(navaid::Config::parse("{}", "<t>", {"planning.route.subroute_m=5"}));
  EXPECT_EQ(c.subroute_m, 5.0);
  EXPECT_EQ(c.window_m, 10.0);
  EXPECT_THROW(sub_route_config(navaid::Config::parse("{}", "<t>", {"planning.route.window_m=0"})), navaid::ConfigError);
}

}  // namespace
