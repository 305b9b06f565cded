// `navaid simulate --from-recording`: the real IMU and ground truth of the EuRoC folders in
// ../shared/data with a simulated camera, then `navaid run` on the result: the estimator meets a
// real IMU (rotor vibration, a 0.077 rad/s gyro bias) on a real flight.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "navaid/io/euroc.hpp"
#include "navaid/io/navaid_recording.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using navaid::testing::navaid_cli;
using navaid::testing::read_text;
using navaid::testing::ScratchDir;

namespace {

fs::path data(const std::string& name) { return navaid::testing::shared_data_dir() / name; }

nlohmann::json json_of(const fs::path& file) { return nlohmann::json::parse(read_text(file)); }

}  // namespace

TEST(SimulateFromRecording, V1_01KeepsTheRealImuAndGroundTruthAndTheEstimatorFollowsTheFlight) {
  if (!navaid::testing::have_shared_data()) return;
  ScratchDir dir("simulate_from_v1_01");
  const fs::path rec = dir / "v1_01";
  const auto sim = navaid_cli("simulate --from-recording '" + data("euroc-V1_01-micro").string() + "' --out '" +
                              rec.string() + "' --set simulation.mode=features --set duration=40");
  ASSERT_EQ(sim.status, 0) << sim.output;
  const auto source = navaid::io::read_euroc(data("euroc-V1_01-micro"));
  const auto written = navaid::io::read_navaid_recording(rec);
  // The IMU samples are the real ones, bit for bit, over the simulated span.
  ASSERT_GT(written.imu.size(), 7900u);
  std::size_t first = 0;
  while (source.imu[first].t < written.imu.front().t) ++first;
  for (std::size_t i = 0; i < written.imu.size(); i += 97) {
    EXPECT_EQ(written.imu[i].t, source.imu[first + i].t);
    EXPECT_EQ(written.imu[i].gyro, source.imu[first + i].gyro);
    EXPECT_EQ(written.imu[i].accel, source.imu[first + i].accel);
  }
  EXPECT_EQ(written.calibration.imu->gyro_noise_density, source.calibration.imu->gyro_noise_density);
  EXPECT_EQ(written.calibration.cameras.at(0).width, 752);  // the folder's own camera
  EXPECT_EQ(written.features.size(), 801u);                 // 40 s at 20 Hz, both ends
  const auto summary = json_of(rec / "summary.json");
  EXPECT_EQ(summary["scenario"], "flight-room");
  EXPECT_GT(summary["walked_m"].get<double>(), 10.0);

  const fs::path out = dir / "run";
  const auto run = navaid_cli("run --recording '" + rec.string() + "' --no-plot --out '" + out.string() + "'");
  ASSERT_EQ(run.status, 0) << run.output;
  const auto s = json_of(out / "summary.json");
  EXPECT_EQ(s["depth"], false);  // EuRoC's camera measures no depth: VIO
  EXPECT_EQ(s["initialization"]["still_gyro_bias"], 1);
  EXPECT_EQ(s["failures"]["map_frame_resets"], 0) << s["failures"].dump();
  EXPECT_LT(s["ate"]["percent_of_path"].get<double>(), 1.0) << s["ate"].dump();

  // The datasheet's noise densities do not cover the rotor vibration: the covariance is too small
  // (measured NEES 40 / 135 over these 40 s); five times the densities bring it towards the error
  // (5.5 / 19.8) at the same accuracy.
  const fs::path scaled = dir / "run-noise-scale-5";
  ASSERT_EQ(navaid_cli("run --recording '" + rec.string() + "' --no-plot --out '" + scaled.string() +
                       "' --set estimator.imu.noise_scale=5")
                .status,
            0);
  const auto s5 = json_of(scaled / "summary.json");
  EXPECT_LT(s5["nees"]["orientation_mean"].get<double>(), 0.5 * s["nees"]["orientation_mean"].get<double>());
  EXPECT_LT(s5["nees"]["position_mean"].get<double>(), 0.5 * s["nees"]["position_mean"].get<double>());
  EXPECT_LT(s5["ate"]["percent_of_path"].get<double>(), 1.0);
}

TEST(SimulateFromRecording, V1_02NeedsAnImuCalibrationAndFliesWithTheRigsCamera) {
  if (!navaid::testing::have_shared_data()) return;
  ScratchDir dir("simulate_from_v1_02");
  const fs::path rec = dir / "v1_02";
  const std::string base = "simulate --from-recording '" + data("euroc-V1_02-imu").string() + "' --out '" + rec.string() +
                           "' --set simulation.mode=features";
  const auto refused = navaid_cli(base);
  EXPECT_NE(refused.status, 0);
  EXPECT_NE(refused.output.find("has no sensor.yaml"), std::string::npos) << refused.output;
  EXPECT_NE(refused.output.find("--imu-calibration"), std::string::npos) << refused.output;
  const fs::path v1_01 = data("euroc-V1_01-micro") / "mav0";
  const auto sim = navaid_cli(base + " --imu-calibration '" + (v1_01 / "imu0" / "sensor.yaml").string() +
                              "' --camera-calibration '" + (v1_01 / "cam0" / "sensor.yaml").string() + "'");
  ASSERT_EQ(sim.status, 0) << sim.output;
  const fs::path out = dir / "run";
  const auto run = navaid_cli("run --recording '" + rec.string() + "' --no-plot --out '" + out.string() + "'");
  ASSERT_EQ(run.status, 0) << run.output;
  const auto s = json_of(out / "summary.json");
  EXPECT_EQ(s["failures"]["map_frame_resets"], 0) << s["failures"].dump();
  EXPECT_GT(s["zero_velocity_frames"].get<int>(), 20);  // 3.5 s on the ground before take-off
  EXPECT_GT(s["ate"]["path_length_m"].get<double>(), 30.0);
  EXPECT_LT(s["ate"]["percent_of_path"].get<double>(), 1.0) << s["ate"].dump();
}

TEST(SimulateFromRecording, ImagesAreRenderedAlongTheFlightAndBadArgumentsAreRefused) {
  if (!navaid::testing::have_shared_data()) return;
  ScratchDir dir("simulate_from_images");
  const fs::path rec = dir / "images";
  const auto sim = navaid_cli("simulate --from-recording '" + data("euroc-V1_01-micro").string() + "' --out '" +
                              rec.string() + "' --set duration=1 --threads 2");
  ASSERT_EQ(sim.status, 0) << sim.output;
  const auto written = navaid::io::read_navaid_recording(rec);
  ASSERT_EQ(written.frames.size(), 21u);
  EXPECT_TRUE(fs::exists(written.frames[10].intensity_path));
  const auto info = navaid_cli("info '" + rec.string() + "'");
  EXPECT_EQ(info.status, 0) << info.output;

  const auto mount = navaid_cli("simulate --from-recording '" + data("euroc-V1_01-micro").string() + "' --mount head --out '" +
                                (dir / "x").string() + "'");
  EXPECT_NE(mount.status, 0);
  EXPECT_NE(mount.output.find("--mount does not apply"), std::string::npos) << mount.output;
  const auto stray = navaid_cli("simulate --scenario corridor --imu-calibration x.yaml --out '" + (dir / "y").string() + "'");
  EXPECT_NE(stray.status, 0);
  EXPECT_NE(stray.output.find("go with --from-recording"), std::string::npos) << stray.output;
  // An IMU without ground truth: nothing to fly the camera along.
  const fs::path imu_only = dir / "imu-only" / "mav0" / "imu0";
  fs::create_directories(imu_only);
  fs::copy_file(data("euroc-V1_01-micro") / "mav0" / "imu0" / "sensor.yaml", imu_only / "sensor.yaml");
  navaid::testing::write_text(imu_only / "data.csv",
                              "#timestamp,wx,wy,wz,ax,ay,az\n1000000000,0,0,0,0,0,9.81\n1005000000,0,0,0,0,0,9.81\n");
  const auto no_gt = navaid_cli("simulate --from-recording '" + (dir / "imu-only").string() + "' --out '" +
                                (dir / "z").string() + "'");
  EXPECT_NE(no_gt.status, 0);
  EXPECT_NE(no_gt.output.find("has no ground truth"), std::string::npos) << no_gt.output;
}
