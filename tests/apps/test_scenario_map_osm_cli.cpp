// End-to-end tests of `navaid scenario-map --osm`: the street scenarios written as OpenStreetMap
// XML with their route truth, byte-identical on a second run, and the refusal for scenarios
// without streets.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "test_support.hpp"

namespace fs = std::filesystem;
using navaid::testing::navaid_cli;
using navaid::testing::read_text;
using navaid::testing::ScratchDir;

namespace {

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) ++n;
  return n;
}

TEST(ScenarioMapOsmCli, Route2WritesTheOsmFileAndItsRouteTruth) {
  const ScratchDir dir("scenario_map_osm_route2");
  const auto run = navaid_cli("scenario-map --scenario route2 --osm --out '" + (dir / "a").string() + "'");
  ASSERT_EQ(run.status, 0) << run.output;
  EXPECT_NE(run.output.find("2 crossing(s)"), std::string::npos) << run.output;
  const std::string osm = read_text(dir / "a" / "map.osm");
  EXPECT_EQ(osm.rfind("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<osm version=\"0.6\" generator=\"navaid\">\n  <bounds ", 0), 0u);
  EXPECT_EQ(count(osm, "<tag k=\"footway\" v=\"crossing\"/>"), 2u);
  EXPECT_EQ(count(osm, "<tag k=\"crossing\" v=\"uncontrolled\"/>"), 2u);
  EXPECT_GE(count(osm, "<tag k=\"footway\" v=\"sidewalk\"/>"), 3u);
  EXPECT_FALSE(fs::exists(dir / "a" / "route2-voxels.csv"));  // --osm writes only the OSM export

  const nlohmann::json t = nlohmann::json::parse(read_text(dir / "a" / "osm_truth.json"));
  EXPECT_EQ(t["scenario"], "route2");
  EXPECT_EQ(t["seed"], 2);
  EXPECT_NEAR(t["length_m"].get<double>(), 300.0, 0.01);  // the documented 300 m walk
  EXPECT_NEAR(t["start"]["lat"].get<double>(), 30.2705, 1e-7);
  EXPECT_NEAR(t["start"]["lon"].get<double>(), 120.1618, 1e-7);
  ASSERT_EQ(t["crossings"].size(), 2u);
  for (const auto& c : t["crossings"]) {
    EXPECT_EQ(c["crossing"], "uncontrolled");
    EXPECT_EQ(c["tactile_paving"], "no");
  }
  EXPECT_EQ(t["landmark"]["name"], "Kexing Unit");
  EXPECT_NE(osm.find("<node id=\"" + std::to_string(t["landmark"]["node_id"].get<int>()) + "\""), std::string::npos);

  const auto again = navaid_cli("scenario-map --scenario route2 --osm --out '" + (dir / "b").string() + "'");
  ASSERT_EQ(again.status, 0) << again.output;
  EXPECT_EQ(read_text(dir / "b" / "map.osm"), osm);
  EXPECT_EQ(read_text(dir / "b" / "osm_truth.json"), read_text(dir / "a" / "osm_truth.json"));
}

TEST(ScenarioMapOsmCli, Route1HasNoCrossingsAndEndsAtTheParkBoard) {
  const ScratchDir dir("scenario_map_osm_route1");
  const auto run = navaid_cli("scenario-map --scenario route1 --osm --seed 9 --out '" + dir.path().string() + "'");
  ASSERT_EQ(run.status, 0) << run.output;
  const nlohmann::json t = nlohmann::json::parse(read_text(dir / "osm_truth.json"));
  EXPECT_EQ(t["seed"], 9);
  EXPECT_NEAR(t["length_m"].get<double>(), 272.0, 0.01);  // 32 m south + 240 m east
  EXPECT_TRUE(t["crossings"].empty());
  EXPECT_EQ(t["landmark"]["name"], "Honoring the Pioneers of Science");
}

TEST(ScenarioMapOsmCli, ScenariosWithoutStreetsAreRefused) {
  const ScratchDir dir("scenario_map_osm_corridor");
  const auto run = navaid_cli("scenario-map --scenario corridor --osm --out '" + dir.path().string() + "'");
  EXPECT_NE(run.status, 0);
  EXPECT_NE(run.output.find("scenario corridor has no streets to export"), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(dir / "map.osm"));
}

}  // namespace
