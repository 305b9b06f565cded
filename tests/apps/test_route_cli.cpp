// End-to-end tests of `navaid route`: the hand-made fixture (known answers), real extracts, and
// every bad input with its exit status (2 bad input, 4 no route).
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "test_support.hpp"

namespace fs = std::filesystem;
using navaid::testing::navaid_cli;
using navaid::testing::read_text;
using navaid::testing::ScratchDir;

namespace {

const std::string kFixture = (fs::path(NAVAID_SOURCE_DIR) / "tests/planning/fixtures/foot_street.osm").string();

nlohmann::json route_json(const fs::path& out) { return nlohmann::json::parse(read_text(out / "route.json")); }

std::string fmt_route(const std::string& osm, double lat1, double lon1, double lat2, double lon2, const std::string& out) {
  char buf[160];
  std::snprintf(buf, sizeof buf, " --from %.7f,%.7f --to %.7f,%.7f", lat1, lon1, lat2, lon2);
  return "route --osm '" + osm + "'" + buf + " --out '" + out + "'";
}

TEST(RouteCli, SignalledCrossingOnTheFixture) {
  const ScratchDir dir("route_cli_fixture");
  const auto run = navaid_cli("route --osm '" + kFixture + "' --from 48.0089029,11.0006720 --to 48.0090827,11.0006720 --out '" +
                              dir.path().string() + "'");
  ASSERT_EQ(run.status, 0) << run.output;
  const nlohmann::json j = route_json(dir.path());
  EXPECT_EQ(j["status"], "found");
  EXPECT_NEAR(j["length_m"].get<double>(), 50.0, 0.5);
  ASSERT_EQ(j["crossings"].size(), 1U);
  EXPECT_EQ(j["crossings"][0]["control"], "traffic_signals");
  EXPECT_EQ(j["crossings"][0]["tactile_paving"], true);
  EXPECT_EQ(j["crossings"][0]["street"], "Ringstrasse");
  EXPECT_GT(j["nodes_expanded"].get<int>(), 0);
  EXPECT_EQ(j["subroutes"].get<int>(), 5);
  EXPECT_NE(read_text(dir / "narration.txt").find("cross Ringstrasse at traffic signals"), std::string::npos);
  const nlohmann::json geo = nlohmann::json::parse(read_text(dir / "route.geojson"));
  EXPECT_EQ(geo["type"], "FeatureCollection");
  EXPECT_EQ(geo["features"][0]["geometry"]["type"], "LineString");
  EXPECT_TRUE(fs::exists(dir / "route.png"));
}

TEST(RouteCli, AvoidStepsByConfigKey) {
  const ScratchDir dir("route_cli_steps");
  const std::string args = "route --osm '" + kFixture + "' --from 48.0179856,11.0000000 --to 48.0179856,11.0005376 --out '";
  const auto steps = navaid_cli(args + (dir / "a").string() + "'");
  ASSERT_EQ(steps.status, 0) << steps.output;
  EXPECT_NEAR(route_json(dir / "a")["steps_m"].get<double>(), 40.0, 0.5);
  const auto ramp = navaid_cli(args + (dir / "b").string() + "' --set planning.route.avoid_steps=true");
  ASSERT_EQ(ramp.status, 0) << ramp.output;
  EXPECT_EQ(route_json(dir / "b")["steps_m"].get<double>(), 0.0);
  EXPECT_NE(read_text(dir / "b" / "narration.txt").find("Café Rampe (amenity=cafe), on your left"), std::string::npos);
}

TEST(RouteCli, NoRouteExitsFour) {
  const ScratchDir dir("route_cli_noroute");
  const auto unreachable = navaid_cli("route --osm '" + kFixture + "' --from 48.0000719,11.0000000 --to 48.0179856,11.0005376 --out '" +
                                      (dir / "u").string() + "'");
  EXPECT_EQ(unreachable.status, 4) << unreachable.output;
  EXPECT_EQ(route_json(dir / "u")["status"], "unreachable");
  EXPECT_NE(read_text(dir / "u" / "narration.txt").find("No route"), std::string::npos);
  const auto off = navaid_cli("route --osm '" + kFixture + "' --from 48.5,11.5 --to 48.0179856,11.0005376 --out '" +
                              (dir / "o").string() + "'");
  EXPECT_EQ(off.status, 4) << off.output;
  EXPECT_EQ(route_json(dir / "o")["status"], "off_graph");
  EXPECT_NE(route_json(dir / "o")["reason"].get<std::string>().find("start"), std::string::npos);
}

TEST(RouteCli, BadInputExitsTwo) {
  const ScratchDir dir("route_cli_bad");
  const std::string out = " --out '" + dir.path().string() + "'";
  const auto missing = navaid_cli("route --osm /nonexistent.osm --from 48,11 --to 48,11" + out);
  EXPECT_EQ(missing.status, 2) << missing.output;
  EXPECT_NE(missing.output.find("no such OSM file"), std::string::npos) << missing.output;
  const fs::path broken = dir / "broken.osm";
  std::ofstream(broken) << "<?xml version=\"1.0\"?>\n<osm version=\"0.6\"><node id=\"1\" lat=\"48\" lon=\"11\">\n";
  const auto xml = navaid_cli("route --osm '" + broken.string() + "' --from 48,11 --to 48,11" + out);
  EXPECT_EQ(xml.status, 2) << xml.output;
  const auto lat = navaid_cli("route --osm '" + kFixture + "' --from 95,11 --to 48,11" + out);
  EXPECT_EQ(lat.status, 2) << lat.output;
  EXPECT_NE(lat.output.find("latitude"), std::string::npos) << lat.output;
  const auto lon = navaid_cli("route --osm '" + kFixture + "' --from 48,11 --to 48,200" + out);
  EXPECT_EQ(lon.status, 2) << lon.output;
  const auto arity = navaid_cli("route --osm '" + kFixture + "' --from 48 --to 48,11" + out);
  EXPECT_EQ(arity.status, 2) << arity.output;
  const auto key = navaid_cli("route --osm '" + kFixture + "' --from 48,11 --to 48,11 --set planning.route.road_factor=0" + out);
  EXPECT_EQ(key.status, 2) << key.output;
  EXPECT_NE(key.output.find("planning.route.road_factor"), std::string::npos) << key.output;
}

TEST(RouteCli, EmptyGraphIsNoRoute) {
  const ScratchDir dir("route_cli_empty");
  const fs::path osm = dir / "buildings.osm";
  std::ofstream(osm) << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<osm version=\"0.6\" generator=\"test\">\n"
                        " <node id=\"1\" lat=\"48.0\" lon=\"11.0\"/>\n <node id=\"2\" lat=\"48.0001\" lon=\"11.0\"/>\n"
                        " <way id=\"3\"><nd ref=\"1\"/><nd ref=\"2\"/><tag k=\"building\" v=\"yes\"/></way>\n</osm>\n";
  const auto run = navaid_cli("route --osm '" + osm.string() + "' --from 48,11 --to 48.0001,11 --out '" + (dir / "o").string() + "'");
  EXPECT_EQ(run.status, 4) << run.output;
  EXPECT_EQ(route_json(dir / "o")["status"], "empty_graph");
}

}  // namespace

namespace {

// The simulator's street scenarios exported as OSM (navaid scenario-map --osm, docs/scenarios.md):
// the route between the truth's start and goal has the truth's length, crossings and landmark.
void check_scenario(const std::string& scenario) {
  const ScratchDir dir("route_cli_" + scenario);
  const auto map = navaid_cli("scenario-map --scenario " + scenario + " --osm --out '" + (dir / "map").string() + "'");
  ASSERT_EQ(map.status, 0) << map.output;
  const nlohmann::json truth = nlohmann::json::parse(read_text(dir / "map" / "osm_truth.json"));
  const auto& s = truth["start"];
  const auto& g = truth["goal"];
  const auto run = navaid_cli(fmt_route((dir / "map" / "map.osm").string(), s["lat"], s["lon"], g["lat"], g["lon"],
                                        (dir / "route").string()));
  ASSERT_EQ(run.status, 0) << run.output;
  const nlohmann::json j = route_json(dir / "route");
  EXPECT_NEAR(j["length_m"].get<double>(), truth["geodesic_length_m"].get<double>(), 0.05) << scenario;
  ASSERT_EQ(j["crossings"].size(), truth["crossings"].size()) << scenario;
  for (std::size_t i = 0; i < j["crossings"].size(); ++i) {
    const auto& c = j["crossings"][i];
    const auto& t = truth["crossings"][i];
    EXPECT_EQ(c["control"], t["crossing"]) << scenario;
    if (!t["tactile_paving"].is_null()) {
      EXPECT_EQ(c["tactile_paving"].get<bool>(), t["tactile_paving"] == "yes") << scenario;
    }
    // The route's crossing starts at the crossing way's first node; the truth counts to its middle node.
    EXPECT_NEAR(c["at_m"].get<double>(), t["at_m"].get<double>(), 6.0) << scenario;
  }
  const std::string narration = read_text(dir / "route" / "narration.txt");
  EXPECT_NE(narration.find("the destination is " + truth["landmark"]["name"].get<std::string>()), std::string::npos)
      << narration;
}

TEST(RouteCli, SimulatedRoute1MatchesItsTruth) { check_scenario("route1"); }
TEST(RouteCli, SimulatedRoute2MatchesItsTruth) { check_scenario("route2"); }

}  // namespace

namespace {

// A real route (the Berlin extract) heard through navaid cues: every turn and crossing of the
// narration is announced 15 m ahead at 1 m/s, and arrival is said at the end.
TEST(RouteCli, TheRealBerlinRouteIsSpokenThroughCues) {
  const ScratchDir dir("route_cli_cues");
  const std::string osm = (navaid::testing::shared_data_dir() / "osm/berlin-siegessaeule.osm.gz").string();
  const auto run = navaid_cli(fmt_route(osm, 52.5145, 13.3480, 52.5145, 13.3522, (dir / "route").string()));
  ASSERT_EQ(run.status, 0) << run.output;
  const std::string narration = read_text(dir / "route" / "narration.txt");
  std::size_t announced = 0;
  for (const char* what : {", turn ", ", cross ", ", steps "}) {
    for (std::size_t p = narration.find(what); p != std::string::npos; p = narration.find(what, p + 1)) ++announced;
  }
  ASSERT_GT(announced, 3u) << narration;
  const std::string timeline = read_text(dir / "route" / "guidance_timeline.csv");
  std::size_t events = 0;
  for (std::size_t p = timeline.find("route_instruction,"); p != std::string::npos;
       p = timeline.find("route_instruction,", p + 1)) {
    ++events;
  }
  EXPECT_EQ(events, announced) << timeline;
  EXPECT_NE(timeline.find("route_instruction,15;left;Fasanerieallee"), std::string::npos) << timeline;
  const auto cues = navaid_cli("cues --guidance '" + (dir / "route" / "guidance_timeline.csv").string() +
                               "' --device belt --speech text --no-figure --out '" + (dir / "cues").string() + "'");
  ASSERT_EQ(cues.status, 0) << cues.output;
  const nlohmann::json s = nlohmann::json::parse(read_text(dir / "cues" / "summary.json"));
  std::size_t route_messages = 0;
  for (const auto& said : s["spoken"]) route_messages += said.get<std::string>().rfind("In 15 meters, ", 0) == 0;
  EXPECT_EQ(route_messages, announced) << s["spoken"].dump();
  EXPECT_EQ(s["spoken"].back(), "You have arrived.");
  EXPECT_NE(s["spoken"].dump().find("In 15 meters, turn left onto Fasanerieallee."), std::string::npos);
  EXPECT_NE(s["spoken"].dump().find("In 15 meters, a crossing: Stra\u00dfe des 17. Juni."), std::string::npos);
}

}  // namespace
