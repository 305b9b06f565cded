// `navaid run` on real EuRoC V1_01 images and IMU (../shared/data/euroc-V1_01-micro: 95 frames,
// 4.7 s, the MAV on the ground with its rotors vibrating it): the still start initializes within
// 1 s, holds without a failure or a reset, and its covariance covers its error.
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

nlohmann::json run_euroc(const ScratchDir& dir, const std::string& name, const std::string& extra) {
  const fs::path euroc = navaid::testing::shared_data_dir() / "euroc-V1_01-micro";
  const fs::path out = dir / name;
  const auto run = navaid_cli("run --recording '" + euroc.string() + "' --no-plot --out '" + out.string() + "'" + extra);
  EXPECT_EQ(run.status, 0) << run.output;
  return nlohmann::json::parse(read_text(out / "summary.json"));
}

}  // namespace

TEST(RealEurocRun, TheStillStartInitializesAtOnceAndHoldsWithAnHonestCovariance) {
  if (!navaid::testing::have_shared_data()) return;
  ScratchDir dir("real_euroc_run");
  const auto s = run_euroc(dir, "run", "");
  EXPECT_LE(s["initialization"]["time_s"].get<double>(), 1.0);
  EXPECT_EQ(s["initialization"]["still_gyro_bias"], 1);  // the camera confirmed the still window
  EXPECT_EQ(s["failures"]["count"], 0) << s["failures"].dump();
  EXPECT_EQ(s["failures"]["map_frame_resets"], 0);
  EXPECT_LT(s["mode_fractions"]["initializing"].get<double>(), 0.15);
  EXPECT_GT(s["mode_fractions"]["vio"].get<double>(), 0.8);
  EXPECT_EQ(s["mode_fractions"]["lost"].get<double>(), 0.0);
  EXPECT_GT(s["zero_velocity_frames"].get<int>(), 60);
  // Standing still it moves millimetres (measured 7 mm), and the error is inside its covariance:
  // per-epoch NEES (3 DOF) below the 95 % upper bound on average (measured 0.8 and 1.6).
  EXPECT_LT(s["ate"]["rmse_m"].get<double>(), 0.02);
  EXPECT_GT(s["nees"]["poses"].get<int>(), 70);
  EXPECT_LT(s["nees"]["position_mean"].get<double>(), 9.35);
  EXPECT_LT(s["nees"]["orientation_mean"].get<double>(), 9.35);
  EXPECT_GT(s["nees"]["orientation_fraction_within_95"].get<double>(), 0.9);
}

TEST(RealEurocRun, WithoutTheStillWindowsGyroBiasTheTracksTriangulateFromDriftAndTheMapResets) {
  // The cause of the old failure, kept as a test: the gyro bias of this IMU is 0.077 rad/s on z;
  // started at 0 +- 0.01 rad/s, the unmodelled turn splits the tracks' rays by more than the
  // triangulation threshold while the body has not moved, the tracks get depths from a few mm of
  // IMU drift, and the solve falls apart.
  if (!navaid::testing::have_shared_data()) return;
  ScratchDir dir("real_euroc_run_ablation");
  const auto s = run_euroc(dir, "run", " --set estimator.initialization.still_gyro_bias=false");
  EXPECT_EQ(s["initialization"]["still_gyro_bias"], 0);
  EXPECT_GE(s["failures"]["map_frame_resets"].get<int>(), 1) << s["failures"].dump();
  EXPECT_GT(s["mode_fractions"]["initializing"].get<double>(), 0.5);
}
