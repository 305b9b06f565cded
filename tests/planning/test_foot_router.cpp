// The foot router on the hand-made fixture (known answers: the sidewalk over the road, the
// signalled crossing over the uncontrolled one, the ramp over the steps when asked), its bad
// inputs, and routes on real extracts.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "navaid/core/errors.hpp"
#include "navaid/planning/foot_router.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using namespace navaid::planning;

namespace {

const fs::path kFixture = fs::path(NAVAID_SOURCE_DIR) / "tests/planning/fixtures/foot_street.osm";

const FootGraph& fixture() {
  static const FootGraph g = load_osm_foot_graph(kFixture);
  return g;
}

// Fixture points (tests/planning/fixtures/foot_street.osm; x east, y north in metres from 48N 11E).
const GeoPoint kA1Start{48.0000719, 11.0000000}, kA1Goal{48.0000719, 11.0026879};
const GeoPoint kA2Start{48.0089029, 11.0006720}, kA2Goal{48.0090827, 11.0006720};
const GeoPoint kA3Start{48.0179856, 11.0000000}, kA3Goal{48.0179856, 11.0005376};

bool uses_way(const Route& r, const FootGraph& g, std::int64_t osm_id) {
  return std::any_of(r.segment_way.begin(), r.segment_way.end(),
                     [&](std::uint32_t w) { return g.ways[w].osm_id == osm_id; });
}

navaid::Config config(std::vector<std::string> overrides) {
  return navaid::Config::parse("{}", "<test>", overrides);
}

TEST(FootRouter, PrefersTheSidewalkOverTheRoad) {
  const FootRouter router(fixture());
  const Route r = router.route(kA1Start, kA1Goal);
  ASSERT_TRUE(r.found()) << r.reason;
  EXPECT_TRUE(uses_way(r, fixture(), 1002));   // the detouring sidewalk, 225 m
  EXPECT_FALSE(uses_way(r, fixture(), 1001));  // not the 200 m road
  EXPECT_NEAR(r.length_m, 2 * std::hypot(100.0, 52.0), 1.0);
  EXPECT_NEAR(r.sidewalk_m, r.length_m, 1.0);
  // Roads as cheap as sidewalks: the shorter way over the road (8 + 200 + 8 m) wins.
  const FootRouter flat(fixture(), foot_route_config(config({"planning.route.road_factor=1"})));
  const Route f = flat.route(kA1Start, kA1Goal);
  ASSERT_TRUE(f.found());
  EXPECT_TRUE(uses_way(f, fixture(), 1001));
  EXPECT_NEAR(f.length_m, 216.0, 1.0);
  EXPECT_NEAR(f.road_m, 200.0, 1.0);
}

TEST(FootRouter, PrefersTheSignalledCrossing) {
  const FootRouter router(fixture());
  const Route r = router.route(kA2Start, kA2Goal);
  ASSERT_TRUE(r.found()) << r.reason;
  EXPECT_TRUE(uses_way(r, fixture(), 2005));   // signals + tactile paving, 15 + 20 + 15 m
  EXPECT_FALSE(uses_way(r, fixture(), 2004));  // uncontrolled, 10 + 20 + 10 m
  EXPECT_NEAR(r.length_m, 50.0, 0.5);
  ASSERT_EQ(r.crossings.size(), 1U);
  EXPECT_EQ(r.crossings[0].info.control, CrossingControl::kTrafficSignals);
  EXPECT_EQ(r.crossings[0].info.tactile_paving, std::optional<bool>(true));
  EXPECT_EQ(r.crossings[0].street, "Ringstrasse");
  // Without a penalty for the uncontrolled crossing, the shorter one wins.
  const FootRouter careless(fixture(), foot_route_config(config({"planning.route.crossing_uncontrolled_m=0"})));
  const Route c = careless.route(kA2Start, kA2Goal);
  ASSERT_TRUE(c.found());
  EXPECT_TRUE(uses_way(c, fixture(), 2004));
  EXPECT_NEAR(c.length_m, 40.0, 0.5);
  ASSERT_EQ(c.crossings.size(), 1U);
  EXPECT_EQ(c.crossings[0].info.control, CrossingControl::kUncontrolled);
}

TEST(FootRouter, TactilePavingMakesACrossingCheaper) {
  // Signals 5 m x tactile 0.5: with a tactile factor of 1 and signals at 25 m, the uncontrolled
  // crossing (30 m, 10 m shorter walk) wins; at tactile 0.2 the signalled one wins again.
  const FootRouter no_tactile(fixture(), foot_route_config(config({"planning.route.crossing_signals_m=25",
                                                                   "planning.route.tactile_factor=1"})));
  EXPECT_TRUE(uses_way(no_tactile.route(kA2Start, kA2Goal), fixture(), 2004));
  const FootRouter tactile(fixture(), foot_route_config(config({"planning.route.crossing_signals_m=25",
                                                                "planning.route.tactile_factor=0.2"})));
  EXPECT_TRUE(uses_way(tactile.route(kA2Start, kA2Goal), fixture(), 2005));
}

TEST(FootRouter, AvoidsStepsWhenConfigured) {
  const FootRouter router(fixture());
  const Route r = router.route(kA3Start, kA3Goal);
  ASSERT_TRUE(r.found());
  EXPECT_TRUE(uses_way(r, fixture(), 3001));  // 40 m of steps x 1.5 < 72 m of ramp
  EXPECT_EQ(r.steps_segments, 1U);
  EXPECT_NEAR(r.steps_m, 40.0, 0.5);
  const FootRouter avoid(fixture(), foot_route_config(config({"planning.route.avoid_steps=true"})));
  const Route a = avoid.route(kA3Start, kA3Goal);
  ASSERT_TRUE(a.found());
  EXPECT_FALSE(uses_way(a, fixture(), 3001));
  EXPECT_TRUE(uses_way(a, fixture(), 3002));
  EXPECT_EQ(a.steps_segments, 0U);
  EXPECT_NEAR(a.length_m, 2 * std::hypot(20.0, 30.0), 0.5);
}

TEST(FootRouter, StartAndGoalOnTheSameEdge) {
  const FootRouter router(fixture());
  const GeoPoint a{48.0089029, 11.0001000}, b{48.0089029, 11.0004000};  // both on the south sidewalk
  const Route r = router.route(a, b);
  ASSERT_TRUE(r.found());
  EXPECT_NEAR(r.length_m, 0.0003 * 111200.0 * std::cos(48.0089 * 3.14159265358979 / 180), 0.5);
}

TEST(FootRouter, OffGraphUnreachableAndOutOfRange) {
  const FootRouter router(fixture());
  const Route off = router.route(GeoPoint{48.5, 11.5}, kA1Goal);
  EXPECT_EQ(off.status, RouteStatus::kOffGraph);
  EXPECT_NE(off.reason.find("start"), std::string::npos);
  const Route off_goal = router.route(kA1Start, GeoPoint{48.0000719 + 0.001, 11.0026879});  // 111 m north
  EXPECT_EQ(off_goal.status, RouteStatus::kOffGraph);
  EXPECT_NE(off_goal.reason.find("destination"), std::string::npos);
  const Route unreachable = router.route(kA1Start, kA3Goal);  // area 1 and area 3 are not connected
  EXPECT_EQ(unreachable.status, RouteStatus::kUnreachable);
  EXPECT_GT(unreachable.expanded, 3U);
  EXPECT_FALSE(unreachable.reason.empty());
  EXPECT_EQ(router.route(GeoPoint{91.0, 11.0}, kA1Goal).status, RouteStatus::kInvalidInput);
  EXPECT_EQ(router.route(kA1Start, GeoPoint{48.0, -181.0}).status, RouteStatus::kInvalidInput);
  EXPECT_EQ(router.route(GeoPoint{std::nan(""), 11.0}, kA1Goal).status, RouteStatus::kInvalidInput);
  const FootGraph empty;
  EXPECT_EQ(FootRouter(empty).route(kA1Start, kA1Goal).status, RouteStatus::kEmptyGraph);
}

TEST(FootRouter, SearchLimitStopsTheSearch) {
  const FootRouter router(fixture(), foot_route_config(config({"planning.route.max_expansions=2"})));
  const Route r = router.route(kA1Start, kA1Goal);
  EXPECT_EQ(r.status, RouteStatus::kSearchLimit);
  EXPECT_EQ(r.expanded, 2U);
}

TEST(FootRouter, BadConfigValuesAreConfigErrors) {
  EXPECT_THROW(foot_route_config(config({"planning.route.road_factor=0.5"})), navaid::ConfigError);
  EXPECT_THROW(foot_route_config(config({"planning.route.tactile_factor=2"})), navaid::ConfigError);
  EXPECT_THROW(foot_route_config(config({"planning.route.max_snap_m=-1"})), navaid::ConfigError);
  EXPECT_THROW(foot_route_config(config({"planning.route.avoid_steps=maybe"})), navaid::ConfigError);
  EXPECT_THROW(foot_route_config(config({"planning.route.crossing_signals_m=x"})), navaid::ConfigError);
}

TEST(FootRouter, SnapsToTheNearestEdge) {
  const FootRouter router(fixture());
  const auto s = router.snap(GeoPoint{48.0089029 + 0.00002, 11.0002000});  // 2.2 m north of the south sidewalk
  ASSERT_TRUE(s);
  EXPECT_EQ(fixture().ways[fixture().edges[s->edge].way].osm_id, 2002);
  EXPECT_NEAR(s->distance_m, 2.2, 0.1);
}

}  // namespace

namespace {

const fs::path kOsm = navaid::testing::shared_data_dir() / "osm";

TEST(FootRouterReal, BerlinAcrossStrasseDes17JuniAtSignals) {
  NAVAID_REQUIRE_SHARED_DATA();
  const FootGraph g = load_osm_foot_graph(kOsm / "berlin-siegessaeule.osm.gz");
  const Route r = FootRouter(g).route(GeoPoint{52.5145, 13.3480}, GeoPoint{52.5145, 13.3522});
  ASSERT_TRUE(r.found()) << r.reason;
  EXPECT_GT(r.length_m, 285.0);  // longer than the straight line (~285 m): round the Großer Stern
  EXPECT_LT(r.length_m, 600.0);
  ASSERT_GE(r.crossings.size(), 1U);
  for (const RouteCrossing& c : r.crossings) {
    EXPECT_EQ(c.info.control, CrossingControl::kTrafficSignals) << c.street;
    EXPECT_EQ(c.street, "Straße des 17. Juni");
  }
}

TEST(FootRouterReal, ParisCrossesAtTactileZebraCrossings) {
  NAVAID_REQUIRE_SHARED_DATA();
  const FootGraph g = load_osm_foot_graph(kOsm / "paris_bss.osm.pbf");
  const Route r = FootRouter(g).route(GeoPoint{48.8620, 2.3600}, GeoPoint{48.8660, 2.3700});
  ASSERT_TRUE(r.found()) << r.reason;
  EXPECT_GT(r.length_m, 850.0);  // straight line ~850 m
  EXPECT_LT(r.length_m, 1400.0);
  ASSERT_GE(r.crossings.size(), 1U);
  for (const RouteCrossing& c : r.crossings) {
    EXPECT_TRUE(c.info.control == CrossingControl::kMarked || c.info.control == CrossingControl::kTrafficSignals);
    EXPECT_EQ(c.info.tactile_paving, std::optional<bool>(true));
  }
}

TEST(FootRouterReal, EveryRealExtractRoutesBetweenTwoOfItsNodes) {
  NAVAID_REQUIRE_SHARED_DATA();
  for (const auto& entry : fs::directory_iterator(kOsm)) {
    const std::string name = entry.path().filename().string();
    if (name.find(".osm") == std::string::npos || name == "melborne.osm.pbf") continue;  // melborne: foot=no everywhere
    const FootGraph g = load_osm_foot_graph(entry.path());
    ASSERT_FALSE(g.empty()) << name;
    // Two ends of the first edge with a neighbour: a route exists and is at least the straight line.
    const FootNode& a = g.nodes[g.edges.front().a];
    const FootNode& b = g.nodes[g.edges.back().b];
    const FootRouter router(g);
    const Route r = router.route(GeoPoint{a.lat_deg, a.lon_deg}, GeoPoint{b.lat_deg, b.lon_deg});
    EXPECT_TRUE(r.found() || r.status == RouteStatus::kUnreachable) << name << ": " << r.reason;
    if (r.found()) {
      EXPECT_GE(r.length_m + 1e-6, haversine_m(a.lat_deg, a.lon_deg, b.lat_deg, b.lon_deg)) << name;
    }
    const Route first = router.route(GeoPoint{a.lat_deg, a.lon_deg}, GeoPoint{g.nodes[g.edges.front().b].lat_deg, g.nodes[g.edges.front().b].lon_deg});
    EXPECT_TRUE(first.found()) << name << ": " << first.reason;
    // The two ends of one edge are connected; the route is at most that edge's cost long.
    EXPECT_LE(first.cost, router.edge_cost(0) + 1e-6) << name;
  }
}

}  // namespace

namespace {

TEST(FootRouter, AnIsolatedPieceNextToTheDestinationDoesNotStrandTheRoute) {
  // A 100 m street footway (1-2) and, 3 m beside the destination, an isolated 5 m courtyard
  // footway (3-4); the destination is 8 m from the street footway.
  const std::string xml = R"(<?xml version="1.0" encoding="UTF-8"?>
<osm version="0.6" generator="test">
 <node id="1" lat="48.0000000" lon="11.0000000"/>
 <node id="2" lat="48.0000000" lon="11.0013441"/>
 <node id="3" lat="48.0001000" lon="11.0010000"/>
 <node id="4" lat="48.0001000" lon="11.0010672"/>
 <way id="10"><nd ref="1"/><nd ref="2"/><tag k="highway" v="footway"/></way>
 <way id="11"><nd ref="3"/><nd ref="4"/><tag k="highway" v="footway"/></way>
</osm>
)";
  const FootGraph g = parse_osm_foot_graph(xml, "osm");
  const FootRouter router(g);
  EXPECT_NE(router.component(0), router.component(2));
  const GeoPoint to{48.0000730, 11.0010300};  // 3.0 m south of the courtyard way, 8.1 m north of the street
  const Route r = router.route(GeoPoint{48.0, 11.0001}, to);
  ASSERT_TRUE(r.found()) << r.reason;
  EXPECT_NEAR(r.goal_snap_m, 8.1, 0.2);
  EXPECT_TRUE(uses_way(r, g, 10));
  EXPECT_FALSE(uses_way(r, g, 11));
  // Beyond max_snap_m the move is refused and the destination stays unreachable.
  FootRouteConfig tight;
  tight.max_snap_m = 5.0;
  EXPECT_EQ(FootRouter(g, tight).route(GeoPoint{48.0, 11.0001}, to).status, RouteStatus::kUnreachable);
}

}  // namespace
