// End-to-end tests of `navaid run`: the estimator on a simulated feature-level walk, and its run folder.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "navaid/io/navaid_recording.hpp"
#include "navaid/io/tum_trajectory.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using navaid::testing::navaid_cli;
using navaid::testing::read_text;
using navaid::testing::ScratchDir;

namespace {

fs::path simulate_features(const ScratchDir& dir) {
  const fs::path out = dir / "walk";
  const auto sim = navaid_cli("simulate --scenario lab-walk-1 --mount hand --seed 5 --out '" + out.string() +
                              "' --set simulation.mode=features --set duration=8 --set sensor.camera.rate=15"
                              " --set features.max_per_frame=80");
  EXPECT_EQ(sim.status, 0) << sim.output;
  return out;
}

}  // namespace

TEST(RunCli, WritesTrajectoryEstimatesAndSummary) {
  ScratchDir dir("run_cli");
  const fs::path rec = simulate_features(dir);
  const fs::path out = dir / "run";
  const auto run = navaid_cli("run --recording '" + rec.string() + "' --out '" + out.string() + "'");
  ASSERT_EQ(run.status, 0) << run.output;
  EXPECT_NE(run.output.find("ATE"), std::string::npos) << run.output;

  const auto traj = navaid::io::read_tum_trajectory(out / "trajectory.tum");
  const auto recording = navaid::io::read_navaid_recording(rec);
  EXPECT_GT(traj.size(), recording.features.size() * 8 / 10);
  EXPECT_LE(traj.size(), recording.features.size());

  std::ifstream csv(out / "estimates.csv");
  std::string header, line;
  std::getline(csv, header);
  EXPECT_EQ(header.rfind("t_ns,px,py,pz,qw,qx,qy,qz,vx,vy,vz,bgx,bgy,bgz,bax,bay,baz,mode,cov_pxx", 0), 0u) << header;
  std::size_t rows = 0, rgbd_vio = 0;
  while (std::getline(csv, line)) {
    ++rows;
    rgbd_vio += line.find(",rgbd-vio,") != std::string::npos;
  }
  EXPECT_EQ(rows, recording.features.size());
  EXPECT_GT(rgbd_vio, rows / 2);

  const auto summary = nlohmann::json::parse(read_text(out / "summary.json"));
  EXPECT_EQ(summary["frames"].get<std::size_t>(), rows);
  EXPECT_GT(summary["keyframes"].get<std::size_t>(), 10u);
  double fractions = 0;
  for (const auto& [mode, f] : summary["mode_fractions"].items()) fractions += f.get<double>();
  EXPECT_NEAR(fractions, 1.0, 1e-9);
  ASSERT_TRUE(summary.contains("ate"));
  EXPECT_LT(summary["ate"]["percent_of_path"].get<double>(), 0.5);
  EXPECT_GT(summary["time_per_frame_ms"]["median"].get<double>(), 0.0);
  EXPECT_TRUE(fs::exists(out / "timing.csv"));
  EXPECT_TRUE(fs::exists(out / "config.yaml"));

  // Ablation keys go through --set; a bad one is a configuration error naming the key.
  const auto vio = navaid_cli("run --recording '" + rec.string() + "' --out '" + (dir / "vio").string() +
                              "' --set estimator.depth.enabled=false");
  ASSERT_EQ(vio.status, 0) << vio.output;
  EXPECT_NE(read_text(dir / "vio" / "estimates.csv").find(",vio,"), std::string::npos);
  const auto bad = navaid_cli("run --recording '" + rec.string() + "' --out '" + (dir / "bad").string() +
                              "' --set estimator.loss.type=l1");
  EXPECT_NE(bad.status, 0);
  EXPECT_NE(bad.output.find("estimator.loss.type"), std::string::npos) << bad.output;
  const auto typo = navaid_cli("run --recording '" + rec.string() + "' --out '" + (dir / "bad").string() +
                               "' --set estimator.windowsize=4");
  EXPECT_NE(typo.status, 0);
  EXPECT_NE(typo.output.find("estimator.windowsize"), std::string::npos) << typo.output;
}

TEST(RunCli, AShockedImuIsDetectedAndTheWindowRestartsInTheSameMapFrame) {
  // A cane striking a kerb: 100 m/s^2 on the accelerometer's x axis for 50 ms, 5 s into the walk.
  ScratchDir dir("run_cli_shock");
  const fs::path rec = dir / "walk";
  const auto sim = navaid_cli("simulate --scenario lab-walk-1 --mount hand --seed 5 --out '" + rec.string() +
                              "' --set simulation.mode=features --set duration=10 --set sensor.camera.rate=15"
                              " --set features.max_per_frame=80 --set 'sensor.imu.shocks=[5.0, 0.05, 100, 0, 0]'");
  ASSERT_EQ(sim.status, 0) << sim.output;
  const auto on = navaid_cli("run --no-plot --recording '" + rec.string() + "' --out '" + (dir / "on").string() + "'");
  ASSERT_EQ(on.status, 0) << on.output;
  EXPECT_NE(on.output.find("implausible"), std::string::npos) << on.output;
  const auto s_on = nlohmann::json::parse(read_text(dir / "on" / "summary.json"));
  EXPECT_GE(s_on["failures"]["count"].get<int>(), 1);
  EXPECT_GE(s_on["failures"]["restarts"].get<int>(), 1);
  EXPECT_EQ(s_on["failures"]["map_frame_resets"].get<int>(), 0);
  EXPECT_LT(s_on["ate"]["percent_of_path"].get<double>(), 1.0) << s_on.dump();
  const auto off = navaid_cli("run --no-plot --recording '" + rec.string() + "' --out '" + (dir / "off").string() +
                              "' --set estimator.failure.detection=false");
  ASSERT_EQ(off.status, 0) << off.output;
  const auto s_off = nlohmann::json::parse(read_text(dir / "off" / "summary.json"));
  EXPECT_EQ(s_off["failures"]["count"].get<int>(), 0);
  EXPECT_GT(s_off["ate"]["percent_of_path"].get<double>(), 5.0) << s_off.dump();
}

TEST(RunCli, RecordingWithoutFeaturesIsAClearError) {
  ScratchDir dir("run_cli_nofeatures");
  const fs::path rec = simulate_features(dir);
  navaid::io::Recording r = navaid::io::read_navaid_recording(rec);
  r.features.clear();
  r.landmarks.clear();
  const fs::path stripped = dir / "imu-only";
  navaid::io::write_navaid_recording(r, stripped);
  const auto run = navaid_cli("run --recording '" + stripped.string() + "' --out '" + (dir / "run").string() + "'");
  EXPECT_NE(run.status, 0);
  EXPECT_NE(run.output.find("no camera data: neither feature observations"), std::string::npos) << run.output;
}
