// End-to-end test of eLabrador's cloud/edge fallback in `navaid map`: with a simulated network
// outage the frames whose labels the segmentation server cannot deliver are mapped with geometry
// only, network.csv records one loss and one recovery, and the map keeps fewer labelled voxels.
#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "test_support.hpp"

namespace fs = std::filesystem;
using navaid::testing::navaid_cli;
using navaid::testing::read_text;
using navaid::testing::ScratchDir;

namespace {

class MapNetworkCli : public ::testing::Test {
 protected:
  // 4 s of the corridor at 10 Hz, 160x120: 41 labelled frames at t = 0, 0.1, ..., 4.0 s.
  // Made once for all the suite's test processes.
  static void SetUpTestSuite() {
    dir_ = std::make_unique<ScratchDir>("map_network_cli");
    inputs_ = navaid::testing::shared_cli_fixture(
        "network-walk", {"simulate --scenario corridor --mount cane --seed 3 --threads 1 --out {dir}/walk"
                         " --set duration=4 --set sensor.camera.resolution=[160,120] --set sensor.camera.rate=10"});
  }
  static void TearDownTestSuite() { dir_.reset(); }
  static fs::path path(const std::string& name) { return *dir_ / name; }
  static navaid::testing::CliRun map(const std::string& out, const std::string& extra) {
    return navaid_cli("map --recording '" + (inputs_ / "walk").string() + "' --poses groundtruth --no-quality --png-every 0 --out '" +
                      path(out).string() + "' " + extra);
  }
  static std::unique_ptr<ScratchDir> dir_;
  static fs::path inputs_;
};

std::unique_ptr<ScratchDir> MapNetworkCli::dir_;
fs::path MapNetworkCli::inputs_;

TEST_F(MapNetworkCli, AnOutageMapsGeometryOnlyUntilTheLinkIsRestored) {
  const auto base = map("base", "");
  ASSERT_EQ(base.status, 0) << base.output;
  EXPECT_FALSE(fs::exists(path("base") / "network.csv"));  // opt-in: no outages, no link
  const auto b = nlohmann::json::parse(read_text(path("base") / "summary.json"));
  EXPECT_FALSE(b.contains("network"));

  // Outage [1, 3) s: the 1 s probe gets no reply (lost at 1.5 s), the 3 s probe restores; the
  // frames at 1.0 .. 2.9 s have no labels.
  const auto r = map("outage", "--set 'mapping.network.outages=[1.0,3.0]'");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("network: 1 of 1 outages detected"), std::string::npos) << r.output;
  EXPECT_EQ(read_text(path("outage") / "network.csv"), "t_s,event\n1.500,lost\n3.000,restored\n");
  const auto s = nlohmann::json::parse(read_text(path("outage") / "summary.json"));
  EXPECT_EQ(s["frames"]["mapped"], b["frames"]["mapped"]);  // the geometry is still mapped
  EXPECT_EQ(s["network"]["outages_detected"].get<std::size_t>(), 1u);
  EXPECT_NEAR(s["network"]["frames_geometry_only"].get<double>(), 20.0, 1.0);
  // Nearly the same geometry (unlabelled frames keep the points of ignored classes such as sky).
  EXPECT_NEAR(s["map"]["occupied_voxels_in_window"].get<double>(), b["map"]["occupied_voxels_in_window"].get<double>(),
              0.02 * b["map"]["occupied_voxels_in_window"].get<double>());
  EXPECT_LT(s["map"]["labelled_voxels_in_window"].get<std::size_t>(),
            b["map"]["labelled_voxels_in_window"].get<std::size_t>());

  // The same outage again: the same map, bit for bit.
  ASSERT_EQ(map("outage-again", "--set 'mapping.network.outages=[1.0,3.0]'").status, 0);
  EXPECT_EQ(read_text(path("outage-again") / "map.ply"), read_text(path("outage") / "map.ply"));
  EXPECT_EQ(read_text(path("outage-again") / "network.csv"), read_text(path("outage") / "network.csv"));
}

// eLabrador's cloud/edge split end to end: the outage reaches the user once, as speech, next to
// the BYU cane's rumble cues from the same map.
TEST_F(MapNetworkCli, TheUserIsToldOnceWhenLabelsStopAndOnceWhenTheyAreBack) {
  const auto r = map("told", "--set 'mapping.network.outages=[1.0,3.0]' --set mapping.obstacles.enabled=true");
  ASSERT_EQ(r.status, 0) << r.output;
  const auto events = read_text(path("told") / "system_events.csv");
  EXPECT_NE(events.find(",event,,,,,,,,network_lost,"), std::string::npos) << events;
  EXPECT_NE(events.find(",event,,,,,,,,network_restored,"), std::string::npos) << events;
  const auto rumble = navaid_cli("rumble --function ficf --scans '" + (path("told") / "obstacle_scan.csv").string() +
                                 "' --out '" + path("told-rumble").string() + "'");
  ASSERT_EQ(rumble.status, 0) << rumble.output;
  const auto cues = navaid_cli("cues --device rumble --speech text --no-figure --guidance '" +
                               (path("told-rumble") / "guidance_timeline.csv").string() + "' --guidance '" +
                               (path("told") / "system_events.csv").string() + "' --out '" + path("told-cues").string() + "'");
  ASSERT_EQ(cues.status, 0) << cues.output;
  const auto s = nlohmann::json::parse(read_text(path("told-cues") / "summary.json"));
  EXPECT_EQ(s["guidance_files"].size(), 2u);
  std::size_t lost = 0, restored = 0;
  for (const auto& said : s["spoken"]) {
    lost += said == "Network lost, object recognition paused.";
    restored += said == "Network restored.";
  }
  EXPECT_EQ(lost, 1u) << s["spoken"].dump();
  EXPECT_EQ(restored, 1u) << s["spoken"].dump();
}

TEST_F(MapNetworkCli, AnEmptyScheduleKeepsEveryLabelAndABadOneNamesTheKey) {
  const auto r = map("empty", "--set 'mapping.network.outages=[]'");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(read_text(path("empty") / "network.csv"), "t_s,event\n");
  const auto s = nlohmann::json::parse(read_text(path("empty") / "summary.json"));
  EXPECT_EQ(s["network"]["frames_geometry_only"].get<std::size_t>(), 0u);

  const auto bad = map("bad", "--set 'mapping.network.outages=[1,3,2,4]'");
  EXPECT_NE(bad.status, 0);
  EXPECT_NE(bad.output.find("mapping.network.outages[1]"), std::string::npos) << bad.output;
  EXPECT_NE(bad.output.find("overlaps"), std::string::npos) << bad.output;
}

}  // namespace
