// Online camera-IMU calibration of the sliding window (estimator.extrinsic.*): started from a wrong
// T_B_C, the window pulls it back towards the simulator's true mount and the trajectory improves.
#include <gtest/gtest.h>

#include <cmath>

#include "navaid/core/errors.hpp"
#include "navaid/estimation/sliding_window_estimator.hpp"
#include "estimator_fixtures.hpp"
#include "test_support.hpp"

namespace navaid::estimation {
namespace {

const io::Recording& walk() {
  static const io::Recording rec = testing::simulate_recording(
      "swc_walk", {"scenario=lab-walk-1", "mount=hand", "simulation.mode=features", "duration=15", "seed=3", "sensor.camera.rate=15"});
  return rec;
}

// The calibration's T_B_C turned by 2 degrees and moved by 3 cm.
io::Recording with_wrong_extrinsic(const io::Recording& rec) {
  io::Recording r = rec;
  SE3& T = r.calibration.cameras.front().T_B_C;
  const Quat dq(Eigen::AngleAxisd(2.0 * M_PI / 180.0, Vec3(1, -2, 1).normalized()));
  T = SE3(dq * T.q, T.t + Vec3(0.03, -0.02, 0.01));
  return r;
}

double rotation_error_deg(const SE3& a, const SE3& b) {
  return Eigen::AngleAxisd(a.q * b.q.conjugate()).angle() * 180.0 / M_PI;
}

using testing::position_rmse;

TEST(SlidingWindowCalibration, OnlineExtrinsicRecoversAWrongMount) {
  const io::Recording& truth = walk();
  const SE3 T_true = truth.calibration.cameras.front().T_B_C;
  const io::Recording wrong = with_wrong_extrinsic(truth);
  const SE3 T_wrong = wrong.calibration.cameras.front().T_B_C;
  ASSERT_NEAR(rotation_error_deg(T_wrong, T_true), 2.0, 1e-9);

  const auto fixed = testing::run_estimator(wrong, {});
  const auto online = testing::run_estimator(wrong, {"estimator.extrinsic.estimate=true"});
  EXPECT_NEAR(rotation_error_deg(fixed.camera_extrinsic, T_wrong), 0.0, 1e-12);  // held by default
  const double rot_err = rotation_error_deg(online.camera_extrinsic, T_true);
  const double trans_err = (online.camera_extrinsic.t - T_true.t).norm();
  RecordProperty("rotation_error_deg", std::to_string(rot_err));
  RecordProperty("translation_error_m", std::to_string(trans_err));
  EXPECT_LT(rot_err, 0.3);
  EXPECT_LT(trans_err, 0.02);

  const double rmse_fixed = position_rmse(fixed.estimates, truth.groundtruth);
  const double rmse_online = position_rmse(online.estimates, truth.groundtruth);
  const double rmse_true = position_rmse(testing::run_estimator(truth, {}).estimates, truth.groundtruth);
  RecordProperty("rmse_wrong_fixed_m", std::to_string(rmse_fixed));
  RecordProperty("rmse_online_m", std::to_string(rmse_online));
  RecordProperty("rmse_true_m", std::to_string(rmse_true));
  EXPECT_LT(rmse_online, rmse_fixed);
}

TEST(SlidingWindowCalibration, OnlineExtrinsicStaysNearATrueCalibration) {
  const io::Recording& truth = walk();
  const SE3 T_true = truth.calibration.cameras.front().T_B_C;
  const auto online = testing::run_estimator(truth, {"estimator.extrinsic.estimate=true"});
  EXPECT_LT(rotation_error_deg(online.camera_extrinsic, T_true), 0.3);
  EXPECT_LT((online.camera_extrinsic.t - T_true.t).norm(), 0.02);
  // The covariance stays a covariance with the extra columns.
  for (const auto& e : online.estimates) {
    ASSERT_TRUE(e.covariance.allFinite());
    ASSERT_GT(e.covariance.diagonal().minCoeff(), 0.0);
  }
}

TEST(SlidingWindowCalibration, OnlineTimeOffsetRecoversTheCameraDelay) {
  // Frames stamped 15 ms early in the camera clock, the calibration says 0.
  const io::Recording rec = testing::simulate_recording(
      "swc_td", {"scenario=lab-walk-1", "mount=hand", "simulation.mode=features", "duration=15", "seed=3",
                 "sensor.camera.rate=15", "sensor.camera.time_offset=0.015", "sensor.camera.time_offset_calibrated=0"});
  ASSERT_EQ(rec.calibration.cameras.front().time_offset_s, 0.0);
  const auto held = testing::run_estimator(rec, {});
  const auto online = testing::run_estimator(rec, {"estimator.time_offset.estimate=true"});
  EXPECT_EQ(held.camera_time_offset_s, 0.0);
  RecordProperty("time_offset_ms", std::to_string(online.camera_time_offset_s * 1e3));
  EXPECT_NEAR(online.camera_time_offset_s, 0.015, 0.002);
  const double rmse_held = position_rmse(held.estimates, rec.groundtruth);
  const double rmse_online = position_rmse(online.estimates, rec.groundtruth);
  RecordProperty("rmse_held_m", std::to_string(rmse_held));
  RecordProperty("rmse_online_m", std::to_string(rmse_online));
  EXPECT_LT(rmse_online, rmse_held);
}

// A restart while the time offset is being estimated: the failed frame is recovered at the time
// it was placed at, which the IMU covers (with the offset its solve had just moved, it could lie
// past the IMU received so far).
TEST(SlidingWindowCalibration, OnlineTimeOffsetSurvivesARestart) {
  const io::Recording rec = testing::simulate_recording(
      "swc_td_shock", {"scenario=lab-walk-1", "mount=hand", "simulation.mode=features", "duration=15", "seed=3",
                       "sensor.camera.rate=15", "sensor.camera.time_offset=0.015",
                       "sensor.camera.time_offset_calibrated=0", "sensor.imu.shocks=[8.0, 0.05, 60, 0, 0]"});
  const auto online = testing::run_estimator(rec, {"estimator.time_offset.estimate=true"}, /*flush=*/false);
  EXPECT_GE(online.stats.failures, 1u) << "the shock must be detected for this test to mean anything";
  EXPECT_FALSE(online.estimates.empty());
  EXPECT_NE(online.estimates.back().mode, EstimatorMode::kLost);
}

TEST(SlidingWindowCalibration, BadSigmaNamesTheKey) {
  const std::string msg = navaid::testing::error_message<ConfigError>(
      [] { testing::run_estimator(walk(), {"estimator.extrinsic.sigma_rotation=0"}); });
  EXPECT_NE(msg.find("estimator.extrinsic.sigma_rotation"), std::string::npos) << msg;
}

}  // namespace
}  // namespace navaid::estimation
