// End-to-end tests of `navaid simulate`: short walks through real scenarios, read back with the
// recording reader and `navaid info`.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "navaid/io/navaid_recording.hpp"
#include "navaid/io/tum_trajectory.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using navaid::testing::folder_contents;
using navaid::testing::navaid_cli;
using navaid::testing::read_text;
using navaid::testing::ScratchDir;

namespace {

// Small and short: 160x120 images, 2 s (1 s still + 1 s walking).
const std::string kSmall = " --set duration=2 --set sensor.camera.resolution=[160,120]";

std::string simulate(const std::string& scenario, const fs::path& out, const std::string& extra) {
  return "simulate --scenario " + scenario + " --out '" + out.string() + "'" + kSmall + extra;
}

}  // namespace

TEST(SimulateCli, ImageModeWritesAReadableRecordingWithGroundTruth) {
  ScratchDir dir("simulate_images");
  const fs::path out = dir / "corridor";
  const auto run = navaid_cli(simulate("corridor", out, " --seed 3 --threads 2"));
  ASSERT_EQ(run.status, 0) << run.output;
  for (const char* f : {"recording.yaml", "calibration.yaml", "imu.csv", "frames.csv", "groundtruth.csv", "mag.csv",
                        "groundtruth.tum", "topview.png", "simulation.yaml", "summary.json", "label_confusion.csv"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  EXPECT_FALSE(fs::exists(out / "gps.csv"));  // indoors: no GNSS by default

  const navaid::io::Recording rec = navaid::io::read_navaid_recording(out);
  ASSERT_EQ(rec.frames.size(), 61u);  // 2 s at 30 Hz, both ends
  ASSERT_FALSE(rec.imu.empty());
  EXPECT_EQ(rec.groundtruth.size(), rec.imu.size());
  EXPECT_EQ(rec.calibration.cameras.at(0).width, 160);
  EXPECT_FALSE(rec.frames[0].confidence_path.empty());
  const auto tum = navaid::io::read_tum_trajectory(out / "groundtruth.tum");
  ASSERT_EQ(tum.size(), rec.groundtruth.size());
  EXPECT_TRUE(tum.back().T_W_B.is_approx(rec.groundtruth.back().T_W_B, 1e-6));

  const auto summary = nlohmann::json::parse(read_text(out / "summary.json"));
  EXPECT_EQ(summary["scenario"], "corridor");
  EXPECT_EQ(summary["frames"], 61);
  EXPECT_GT(summary["valid_depth_fraction"].get<double>(), 0.3);

  const auto info = navaid_cli("info '" + out.string() + "'");
  EXPECT_EQ(info.status, 0) << info.output;
}

TEST(SimulateCli, SameSeedSameFilesWhateverTheCacheAndThreads) {
  ScratchDir dir("simulate_determinism");
  const fs::path cache = dir / "cache";
  ASSERT_EQ(navaid_cli(simulate("corridor", dir / "a", " --seed 5 --threads 1")).status, 0);
  ASSERT_EQ(navaid_cli(simulate("corridor", dir / "b", " --seed 5 --threads 2 --cache '" + cache.string() + "'")).status, 0);
  const auto warm = navaid_cli(simulate("corridor", dir / "c", " --seed 5 --cache '" + cache.string() + "'"));
  ASSERT_EQ(warm.status, 0) << warm.output;
  EXPECT_NE(warm.output.find("(0 rendered)"), std::string::npos) << warm.output;  // all from the cache
  const auto a = folder_contents(dir / "a"), b = folder_contents(dir / "b"), c = folder_contents(dir / "c");
  ASSERT_EQ(a.size(), b.size());
  for (const auto& [name, bytes] : a) {
    if (name == "summary.json") continue;  // holds wall times
    EXPECT_TRUE(b.at(name) == bytes) << name << " differs with 2 threads and a cold cache";
    EXPECT_TRUE(c.at(name) == bytes) << name << " differs with a warm cache";
  }
  // Another seed changes the noise, not the ground truth.
  ASSERT_EQ(navaid_cli(simulate("corridor", dir / "d", " --seed 6 --cache '" + cache.string() + "'")).status, 0);
  const auto d = folder_contents(dir / "d");
  EXPECT_EQ(d.at("groundtruth.tum"), a.at("groundtruth.tum"));
  EXPECT_NE(d.at("imu.csv"), a.at("imu.csv"));
}

TEST(SimulateCli, SimulationYamlHoldsTheWholeConfigurationAndReproducesTheRecording) {
  ScratchDir dir("simulate_yaml");
  ASSERT_EQ(navaid_cli(simulate("corridor", dir / "a", " --seed 4 --set simulation.mode=features")).status, 0);
  const std::string yaml = read_text(dir / "a" / "simulation.yaml");
  // Defaults nobody set are written too: the walker's gait, the IMU noise, the features' limits.
  for (const char* key : {"scan_amplitude:", "gyro_noise_density:", "max_per_frame:", "still_time:", "seed: 4"})
    EXPECT_NE(yaml.find(key), std::string::npos) << key << " missing from\n" << yaml;
  const auto again = navaid_cli("simulate --config '" + (dir / "a" / "simulation.yaml").string() + "' --out '" +
                                (dir / "b").string() + "'");
  ASSERT_EQ(again.status, 0) << again.output;
  const auto a = folder_contents(dir / "a"), b = folder_contents(dir / "b");
  for (const auto& [name, bytes] : a) {
    if (name == "summary.json") continue;  // holds wall times
    EXPECT_TRUE(b.at(name) == bytes) << name << " differs when simulated from simulation.yaml";
  }
}

TEST(SimulateCli, FeatureModeWritesObservationsAndLandmarks) {
  ScratchDir dir("simulate_features");
  const fs::path out = dir / "route1";
  const auto run = navaid_cli(simulate("route1", out, " --set simulation.mode=features --set duration=6"));
  ASSERT_EQ(run.status, 0) << run.output;
  const navaid::io::Recording rec = navaid::io::read_navaid_recording(out);
  EXPECT_TRUE(rec.frames.empty());
  ASSERT_GT(rec.features.size(), 150u);
  ASSERT_FALSE(rec.landmarks.empty());
  EXPECT_FALSE(rec.gps.empty());  // outdoors
  std::size_t observations = 0;
  for (const auto& f : rec.features) observations += f.features.size();
  EXPECT_GT(observations / rec.features.size(), 50u);
}

TEST(SimulateCli, BadInputIsAClearError) {
  ScratchDir dir("simulate_errors");
  auto run = navaid_cli("simulate --scenario atlantis --out '" + (dir / "x").string() + "'");
  EXPECT_NE(run.status, 0);
  EXPECT_NE(run.output.find("route1"), std::string::npos) << run.output;  // lists the known names
  run = navaid_cli(simulate("corridor", dir / "y", " --set sensor.imu.rat=400"));
  EXPECT_NE(run.status, 0);
  EXPECT_NE(run.output.find("sensor.imu.rat"), std::string::npos) << run.output;
  run = navaid_cli(simulate("corridor", dir / "z", " --mount shoulder"));
  EXPECT_NE(run.status, 0);
  EXPECT_NE(run.output.find("head, cane, hand"), std::string::npos) << run.output;
  run = navaid_cli("simulate --list");
  EXPECT_EQ(run.status, 0);
  EXPECT_NE(run.output.find("lab-walk-5"), std::string::npos) << run.output;
}

TEST(ScenarioMapCli, ExportsVoxelsOccupancyAndTopView) {
  ScratchDir dir("scenario_map");
  const auto run = navaid_cli("scenario-map --scenario corridor --resolution 0.1 --out '" + dir.path().string() + "'");
  ASSERT_EQ(run.status, 0) << run.output;
  for (const char* f : {"corridor-voxels.csv", "corridor-occupancy.pgm", "corridor-occupancy.yaml", "corridor-topview.png"})
    EXPECT_TRUE(fs::exists(dir / f)) << f;
  const std::string pgm = read_text(dir / "corridor-occupancy.pgm");
  EXPECT_EQ(pgm.rfind("P5", 0), 0u);
  EXPECT_NE(read_text(dir / "corridor-occupancy.yaml").find("resolution: 0.1"), std::string::npos);
  EXPECT_NE(read_text(dir / "corridor-voxels.csv").find(",wall"), std::string::npos);
  const auto bad = navaid_cli("scenario-map --scenario corridor --band 2 1 --out '" + (dir / "x").string() + "'");
  EXPECT_NE(bad.status, 0);
  EXPECT_NE(bad.output.find("--band"), std::string::npos) << bad.output;
}
