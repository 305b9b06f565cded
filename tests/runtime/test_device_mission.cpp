// What the user asks a device for while it runs: "go to <place>" on a route's streets resolves to
// a route from where the estimate puts the user to the named landmark (runtime::street_places),
// on a real OpenStreetMap extract.
#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <string>

#include "navaid/planning/osm_foot_graph.hpp"
#include "navaid/planning/route_subgoals.hpp"
#include "navaid/runtime/device_mission.hpp"
#include "test_support.hpp"

namespace navaid::runtime {
namespace {

RouteMission berlin_streets() {
  const auto osm = navaid::testing::shared_data_dir() / "osm/berlin-siegessaeule.osm.gz";
  planning::FootGraph streets = planning::load_osm_foot_graph(osm);
  const planning::FootNode start = streets.nodes.front();
  const GeodeticOrigin origin{start.lat_deg, start.lon_deg, 0.0};
  return RouteMission{std::move(streets), osm.string(), {start.lat_deg, start.lon_deg}, {start.lat_deg, start.lon_deg},
                      std::nullopt, origin};
}

/// The landmark's name as a user says it: upper case, with spaces doubled.
std::string as_said(const std::string& name) {
  std::string said = "  ";
  for (const char c : name) said += c == ' ' ? std::string("  ") : std::string(1, static_cast<char>(std::toupper(c)));
  return said;
}

TEST(StreetPlaces, GoToALandmarkRoutesFromWhereTheUserIs) {
  NAVAID_REQUIRE_SHARED_DATA();
  const RouteMission streets = berlin_streets();
  const planning::Landmark* landmark = nullptr;
  for (const auto& l : streets.streets.landmarks)
    if (!l.name.empty() && !landmark) landmark = &l;
  ASSERT_NE(landmark, nullptr) << "the extract has no named landmark";
  const PlaceResolver places = street_places(streets);

  // Registered: the route starts at the estimate's position, 30 m east and 40 m north of the origin.
  StateEstimate now;
  now.T_W_B.t = Vec3(40.0, -30.0, 1.0);
  now.T_ENU_W = SE3(Quat(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ())), Vec3::Zero());  // W's x is north
  const auto mission = places(as_said(landmark->name), now);
  ASSERT_TRUE(mission.has_value());
  ASSERT_TRUE(mission->route.has_value());
  const planning::Vec2 from_ENU = planning::LocalEnu(streets.origin).to_enu(mission->route->from);
  EXPECT_NEAR(from_ENU.x(), 30.0, 1e-6);
  EXPECT_NEAR(from_ENU.y(), 40.0, 1e-6);
  EXPECT_DOUBLE_EQ(mission->route->to.lat_deg, landmark->lat_deg);
  EXPECT_DOUBLE_EQ(mission->route->to.lon_deg, landmark->lon_deg);
  ASSERT_TRUE(mission->route->face.has_value());  // facing the landmark on arrival
  EXPECT_DOUBLE_EQ(mission->route->face->lat_deg, landmark->lat_deg);
  EXPECT_EQ(mission->route->streets.landmarks.size(), streets.streets.landmarks.size());
  // The new mission knows the places too: the user may name another later.
  ASSERT_TRUE(mission->place);
  EXPECT_TRUE(mission->place(landmark->name, now).has_value());

  // Before the registration the route starts where the mission did.
  const auto unregistered = places(landmark->name, StateEstimate{});
  ASSERT_TRUE(unregistered.has_value());
  EXPECT_DOUBLE_EQ(unregistered->route->from.lat_deg, streets.from.lat_deg);
  EXPECT_DOUBLE_EQ(unregistered->route->from.lon_deg, streets.from.lon_deg);

  EXPECT_FALSE(places("the moon", now).has_value());
  EXPECT_FALSE(places("", now).has_value());
}

TEST(StreetPlaces, GeodeticPositionNeedsTheRegistration) {
  const GeodeticOrigin origin{52.5, 13.35, 0.0};
  StateEstimate e;
  e.T_W_B.t = Vec3(10.0, 0.0, 0.0);
  EXPECT_FALSE(geodetic_position(e, origin).has_value());
  e.T_ENU_W = SE3();
  const auto p = geodetic_position(e, origin);
  ASSERT_TRUE(p.has_value());
  EXPECT_NEAR(p->lat_deg, 52.5, 1e-9);
  EXPECT_GT(p->lon_deg, 13.35);  // 10 m east
  EXPECT_NEAR((p->lon_deg - 13.35) * 111320.0 * std::cos(52.5 * M_PI / 180.0), 10.0, 0.05);
}

}  // namespace
}  // namespace navaid::runtime
