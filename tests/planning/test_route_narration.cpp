// Turn-by-turn text on the hand-made fixture: turns, crossings with their control and tactile
// paving and the street crossed, steps, and the final landmark with its side.
#include <gtest/gtest.h>

#include <filesystem>

#include "navaid/planning/route_narration.hpp"

namespace fs = std::filesystem;
using namespace navaid::planning;

namespace {

const FootGraph& fixture() {
  static const FootGraph g = load_osm_foot_graph(fs::path(NAVAID_SOURCE_DIR) / "tests/planning/fixtures/foot_street.osm");
  return g;
}

std::string joined(const std::vector<Instruction>& lines) {
  std::string s;
  for (const Instruction& i : lines) s += i.text + "\n";
  return s;
}

TEST(RouteNarration, SignalledCrossingWithTurns) {
  const Route r = FootRouter(fixture()).route(GeoPoint{48.0089029, 11.0006720}, GeoPoint{48.0090827, 11.0006720});
  ASSERT_TRUE(r.found());
  const auto lines = narrate_route(r, fixture());
  const std::string text = joined(lines);
  ASSERT_EQ(lines.size(), 5U) << text;
  EXPECT_EQ(lines[0].text, "Head east along the sidewalk.");
  EXPECT_EQ(lines[1].text, "After 15 m, turn left.") << text;
  EXPECT_EQ(lines[2].text, "Then cross Ringstrasse at traffic signals, tactile paving.") << text;
  EXPECT_EQ(lines[3].kind, InstructionKind::kTurn);
  EXPECT_NEAR(lines[3].turn_deg, 90.0, 1.0);
  EXPECT_EQ(lines[3].text, "After 20 m, turn left.");
  EXPECT_EQ(lines[4].text, "After 15 m, you have arrived at the destination.");
}

TEST(RouteNarration, UncontrolledCrossingSaysSo) {
  FootRouteConfig c;
  c.crossing_uncontrolled_m = 0;
  const Route r = FootRouter(fixture(), c).route(GeoPoint{48.0089029, 11.0006720}, GeoPoint{48.0090827, 11.0006720});
  ASSERT_TRUE(r.found());
  const std::string text = joined(narrate_route(r, fixture()));
  EXPECT_NE(text.find("cross Ringstrasse at an uncontrolled crossing (no signals), no tactile paving."), std::string::npos)
      << text;
  EXPECT_NE(text.find("turn right"), std::string::npos) << text;  // west first, then north: right
}

TEST(RouteNarration, StepsAndTheLandmarkOnTheLeft) {
  const GeoPoint a{48.0179856, 11.0000000}, b{48.0179856, 11.0005376};
  const Route steps = FootRouter(fixture()).route(a, b);
  ASSERT_TRUE(steps.found());
  const auto s = narrate_route(steps, fixture());
  const std::string text = joined(s);
  EXPECT_EQ(s.front().text, "Head east along the steps.") << text;
  EXPECT_NE(text.find("Then steps for 40 m."), std::string::npos) << text;
  EXPECT_EQ(s.back().text, "After 40 m, the destination is Café Rampe (amenity=cafe), on your left.") << text;

  FootRouteConfig avoid;
  avoid.avoid_steps = true;
  const Route ramp = FootRouter(fixture(), avoid).route(a, b);
  const auto r = narrate_route(ramp, fixture());
  const std::string rtext = joined(r);
  EXPECT_EQ(r.front().text, "Head north-east along Rampenweg.") << rtext;
  EXPECT_EQ(rtext.find("steps"), std::string::npos) << rtext;
  ASSERT_EQ(r.size(), 3U) << rtext;
  EXPECT_EQ(r[1].text, "After 36 m, turn right.");  // 56 deg up, 56 deg down: 113 deg
  EXPECT_NE(r[2].text.find("on your left"), std::string::npos);
  // Landmarks beyond the radius are not named.
  NarrationConfig none;
  none.landmark_radius_m = 1.0;
  EXPECT_EQ(narrate_route(ramp, fixture(), none).back().text, "After 36 m, you have arrived at the destination.");
}

TEST(RouteNarration, NoRouteNoText) {
  Route r;
  r.status = RouteStatus::kUnreachable;
  EXPECT_TRUE(narrate_route(r, fixture()).empty());
}

}  // namespace
