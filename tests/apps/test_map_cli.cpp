// End-to-end tests of `navaid map` and of `navaid run --set mapping.enabled=true` on a rendered
// corridor walk with the cane rig: the map folder, quality against the simulated world, the same
// map from the run's estimates afterwards as during the run, and the errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "test_support.hpp"

namespace fs = std::filesystem;
using navaid::testing::navaid_cli;
using navaid::testing::read_text;
using navaid::testing::ScratchDir;

namespace {

class MapCli : public ::testing::Test {
 protected:
  // One rendered walk for the suite: 6 s of the corridor (1 s still start), cane mount, 320x240 at
  // 15 Hz, and a mapping run on it (made once for all the suite's test processes).
  static void SetUpTestSuite() {
    dir_ = std::make_unique<ScratchDir>("map_cli");
    inputs_ = navaid::testing::shared_cli_fixture(
        "map-cli-walk", {"simulate --scenario corridor --mount cane --seed 3 --threads 1 --out {dir}/walk"
                         " --set duration=6 --set sensor.camera.resolution=[320,240] --set sensor.camera.rate=15",
                         "run --recording {dir}/walk --out {dir}/run --set mapping.enabled=true --no-plot"});
  }
  static void TearDownTestSuite() { dir_.reset(); }
  static fs::path path(const std::string& name) { return *dir_ / name; }
  static fs::path input(const std::string& name) { return inputs_ / name; }
  static std::unique_ptr<ScratchDir> dir_;
  static fs::path inputs_;
};

std::unique_ptr<ScratchDir> MapCli::dir_;
fs::path MapCli::inputs_;

TEST_F(MapCli, GroundTruthPosesGiveAMapFolderWithQuality) {
  const fs::path out = path("map-gt");
  const auto r = navaid_cli("map --recording '" + input("walk").string() + "' --poses groundtruth --out '" +
                            out.string() + "'");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("quality: occupancy precision"), std::string::npos) << r.output;
  for (const char* f : {"map.ot", "map-color.ot", "map.ply", "topview.png", "timing.csv", "summary.json", "config.yaml"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  EXPECT_NE(read_text(out / "map.ot").find("id SemanticOcTree-max"), std::string::npos);
  EXPECT_NE(read_text(out / "map-color.ot").find("id ColorOcTree"), std::string::npos);
  const auto s = nlohmann::json::parse(read_text(out / "summary.json"));
  EXPECT_EQ(s["poses"], "groundtruth");
  EXPECT_GT(s["frames"]["mapped"].get<std::size_t>(), 60u);
  EXPECT_EQ(s["frames"]["not_localised"].get<std::size_t>(), 0u);
  const auto& q = s["quality"];
  EXPECT_GT(q["occupancy"]["precision"].get<double>(), 0.9);
  EXPECT_GT(q["occupancy"]["recall"].get<double>(), 0.6);
  EXPECT_GT(q["semantic_accuracy"].get<double>(), 0.6);
  ASSERT_EQ(q["obstacles"].size(), 3u);  // the corridor's low box, hanging sign and cabinet
  ASSERT_EQ(s["memory"].size(), 4u);
  EXPECT_GT(s["time_per_mapped_frame_ms"]["median"].get<double>(), 0.0);
}

TEST_F(MapCli, TheRunMapsAsItGoesAndNavaidMapRebuildsTheSameMapFromItsEstimates) {
  const auto run_summary = nlohmann::json::parse(read_text(input("run") / "summary.json"));
  ASSERT_TRUE(run_summary.contains("mapping"));
  const std::size_t mapped = run_summary["mapping"]["frames"]["mapped"].get<std::size_t>();
  EXPECT_GT(mapped, 40u);
  EXPECT_GT(run_summary["mapping"]["frames"]["not_localised"].get<std::size_t>(), 0u);  // the still start initializes
  const fs::path out = path("map-est");
  const auto r = navaid_cli("map --recording '" + input("walk").string() + "' --run '" + input("run").string() +
                            "' --out '" + out.string() + "'");
  ASSERT_EQ(r.status, 0) << r.output;
  const auto s = nlohmann::json::parse(read_text(out / "summary.json"));
  EXPECT_EQ(s["frames"]["mapped"].get<std::size_t>(), mapped);
  EXPECT_EQ(read_text(out / "map.ply"), read_text(input("run") / "map" / "map.ply"));
}

TEST_F(MapCli, TheObstaclePipelineWritesAScanPerFrame) {
  const fs::path out = path("map-obstacles");
  const auto r = navaid_cli("map --recording '" + input("walk").string() + "' --poses groundtruth --out '" +
                            out.string() + "' --set mapping.obstacles.enabled=true --png-every 0");
  ASSERT_EQ(r.status, 0) << r.output;
  std::istringstream csv(read_text(out / "obstacle_scan.csv"));
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(std::count(line.begin(), line.end(), ','), 4 + 2 * 61);  // five counters, r_ and d_ bins -30 .. 30 deg
  std::size_t rows = 0, ransac = 0, with_obstacles = 0;
  while (std::getline(csv, line)) {
    ++rows;
    std::stringstream fields(line);
    std::vector<std::string> f;
    for (std::string x; std::getline(fields, x, ',');) f.push_back(x);
    ransac += f.at(2) == "1";
    with_obstacles += std::stoul(f.at(3)) > 0;
  }
  const auto s = nlohmann::json::parse(read_text(out / "summary.json"));
  EXPECT_EQ(rows, s["frames"]["mapped"].get<std::size_t>());
  EXPECT_GT(ransac, rows * 9 / 10);           // the corridor floor is found
  EXPECT_GT(with_obstacles, rows * 9 / 10);   // walls and the stations are always in view
  EXPECT_FALSE(fs::exists(out / "snapshots"));  // --png-every 0: the final PNGs only
  EXPECT_TRUE(fs::exists(out / "cost.png"));
}

TEST_F(MapCli, ARunOfAnotherRecordingIsRejected) {
  const fs::path other = path("other");
  ASSERT_EQ(navaid_cli("simulate --scenario corridor --mount cane --seed 4 --threads 1 --out '" + other.string() +
                       "' --set duration=3 --set sensor.camera.resolution=[160,120] "
                       "--set sensor.camera.rate=5")
                .status,
            0);
  const auto r = navaid_cli("map --recording '" + other.string() + "' --run '" + input("run").string() + "' --out '" +
                            path("bad").string() + "'");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("estimates.csv"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("does not match the recording"), std::string::npos) << r.output;
}

TEST_F(MapCli, ABadCovarianceInTheRunIsAnErrorNamingTheFile) {
  // Copy the run and make one estimate's position covariance negative (not positive definite).
  const fs::path bad = path("bad-run");
  fs::create_directories(bad);
  std::istringstream in(read_text(input("run") / "estimates.csv"));
  std::ostringstream out;
  std::string line;
  std::getline(in, line);
  out << line << "\n";
  const auto columns = [](const std::string& l) {
    std::vector<std::string> v;
    std::stringstream ss(l);
    for (std::string f; std::getline(ss, f, ',');) v.push_back(f);
    return v;
  };
  const auto header = columns(line);
  const auto col = std::find(header.begin(), header.end(), "cov_pxx") - header.begin();
  for (int row = 0; std::getline(in, line); ++row) {
    auto f = columns(line);
    if (row == 40) f[static_cast<std::size_t>(col)] = "-0.5";
    for (std::size_t i = 0; i < f.size(); ++i) out << (i ? "," : "") << f[i];
    out << "\n";
  }
  navaid::testing::write_text(bad / "estimates.csv", out.str());
  const auto r = navaid_cli("map --recording '" + input("walk").string() + "' --run '" + bad.string() + "' --out '" +
                            path("bad-map").string() + "'");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("estimates.csv"), std::string::npos) << r.output;
  EXPECT_TRUE(r.output.find("not positive definite") != std::string::npos ||
              r.output.find("covariance") != std::string::npos)
      << r.output;
}

TEST_F(MapCli, UsageErrors) {
  const auto no_run = navaid_cli("map --recording '" + input("walk").string() + "' --out '" + path("x").string() + "'");
  EXPECT_NE(no_run.status, 0);
  EXPECT_NE(no_run.output.find("--run is required"), std::string::npos) << no_run.output;
  const auto bad_key = navaid_cli("map --recording '" + input("walk").string() + "' --poses groundtruth --out '" +
                                  path("y").string() + "' --set mapping.map.fusion=mean");
  EXPECT_NE(bad_key.status, 0);
  EXPECT_NE(bad_key.output.find("mapping.map.fusion"), std::string::npos) << bad_key.output;
}

}  // namespace
