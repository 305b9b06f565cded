// Failure detection and recovery of the sliding-window estimator (estimator.failure.*): the
// detection's limits on hand-made states, and simulated feature-level walks whose IMU takes a
// shock (a cane striking a kerb: the accelerometer reads a large force for a few samples).
#include <gtest/gtest.h>

#include <cmath>
#include <optional>

#include "navaid/core/errors.hpp"
#include "navaid/estimation/failure_detection.hpp"
#include "navaid/estimation/sliding_window_estimator.hpp"
#include "estimator_fixtures.hpp"
#include "test_support.hpp"

namespace navaid::estimation {
namespace {

// ---------------------------------------------------------------------------------------------
// detect_estimator_failure

StateEstimate walking(Timestamp t, const Vec3& p) {
  StateEstimate e;
  e.t = t;
  e.T_W_B = SE3(Quat::Identity(), p);
  e.v_W = Vec3(1.2, 0, 0);
  e.b_g = Vec3(0.01, 0, 0);
  e.b_a = Vec3(0.1, 0, 0);
  e.mode = EstimatorMode::kRgbdVio;
  return e;
}

constexpr Timestamp kFrame = 33'333'333;  // 30 Hz

TEST(FailureDetection, APlausibleSuccessorPasses) {
  const StateEstimate a = walking(0, Vec3::Zero());
  const StateEstimate b = walking(kFrame, Vec3(0.04, 0, 0));
  const FailureThresholds limits;
  EXPECT_FALSE(detect_estimator_failure(b, &a, {80, 78}, limits));
  EXPECT_FALSE(detect_estimator_failure(b, nullptr, {80, 78}, limits));
  // Too few residuals to judge the inlier share.
  EXPECT_FALSE(detect_estimator_failure(b, &a, {7, 0}, limits));
}

TEST(FailureDetection, NamesEachImplausibility) {
  const FailureThresholds limits;
  const StateEstimate a = walking(0, Vec3::Zero());
  auto reason = [&](StateEstimate b, VisualSupport support = {80, 80}) {
    const auto why = detect_estimator_failure(b, &a, support, limits);
    return why ? *why : std::string("none");
  };
  StateEstimate b = walking(kFrame, Vec3(0.04, 0, 0));
  StateEstimate x = b;
  x.b_a = Vec3(0, 2.6, 0);
  EXPECT_NE(reason(x).find("accelerometer bias 2.6"), std::string::npos) << reason(x);
  x = b;
  x.b_g = Vec3(0, 0, -1.1);
  EXPECT_NE(reason(x).find("gyro bias 1.1"), std::string::npos) << reason(x);
  x = b;
  x.v_W = Vec3(0, 10.5, 0);
  EXPECT_NE(reason(x).find("speed 10.5"), std::string::npos) << reason(x);
  // Position against the previous position moved by its velocity: 0.04 m expected, 1.2 m is a jump.
  x = b;
  x.T_W_B.t = Vec3(1.24, 0, 0);
  EXPECT_NE(reason(x).find("position jump 1.2"), std::string::npos) << reason(x);
  x.T_W_B.t = Vec3(0.04 + 0.99, 0, 0);
  EXPECT_EQ(reason(x), "none");
  x = b;
  x.T_W_B.q = Quat(Eigen::AngleAxisd(0.9, Vec3::UnitZ()));
  EXPECT_NE(reason(x).find("rotation jump 0.9"), std::string::npos) << reason(x);
  x.T_W_B.q = Quat(Eigen::AngleAxisd(0.85, Vec3::UnitZ()));
  EXPECT_EQ(reason(x), "none");
  EXPECT_NE(reason(b, {40, 19}).find("visual inliers 19 of 40"), std::string::npos) << reason(b, {40, 19});
  EXPECT_EQ(reason(b, {40, 20}), "none");
  x = b;
  x.v_W.x() = std::nan("");
  EXPECT_EQ(reason(x), "state not finite");
}

// ---------------------------------------------------------------------------------------------
// On walks

const io::Recording& failure_walk() {
  static const io::Recording rec = testing::simulate_recording(
      "swf_walk", {"scenario=lab-walk-1", "mount=hand", "simulation.mode=features", "duration=12", "seed=3",
                   "sensor.camera.rate=15", "features.max_per_frame=80"});
  return rec;
}

// The walk with `accel` added to the specific force for 50 ms from 6 s after the first frame.
io::Recording with_shock(const Vec3& accel) {
  io::Recording rec = failure_walk();
  const Timestamp t0 = rec.features.front().t;
  for (auto& s : rec.imu) {
    const double t = ns_to_seconds(s.t - t0);
    if (t >= 6.0 && t < 6.05) s.accel += accel;
  }
  return rec;
}

// Largest position error over [from, to) s after the first frame, the estimate mapped onto the
// ground truth by the 4-DOF alignment at its first estimate at or after `align_from` s.
double max_error(const std::vector<StateEstimate>& est, const io::Recording& rec, double from, double to,
                 double align_from = 0) {
  const Timestamp t0 = rec.features.front().t;
  std::optional<SE3> align;  // W of the estimate to the ground truth's world
  double worst = 0;
  for (const auto& s : est) {
    const double t = ns_to_seconds(s.t - t0);
    if (s.mode == EstimatorMode::kInitializing || t < align_from) continue;
    const SE3 g = testing::groundtruth_at(rec.groundtruth, s.t);
    if (!align) {
      const Quat q(Eigen::AngleAxisd(yaw_of(g.q) - yaw_of(s.T_W_B.q), Vec3::UnitZ()));
      align = SE3(q, g.t - q * s.T_W_B.t);
    }
    if (t >= from && t < to) worst = std::max(worst, ((*align * s.T_W_B).t - g.t).norm());
  }
  return worst;
}

TEST(SlidingWindowFailure, ANormalWalkHasNoFailure) {
  const auto run = testing::run_estimator(failure_walk(), {});
  EXPECT_EQ(run.stats.failures, 0u) << run.stats.last_failure;
  EXPECT_EQ(run.stats.restarts, 0u);
  EXPECT_LT(max_error(run.estimates, failure_walk(), 0, 12), 0.05);
}

TEST(SlidingWindowFailure, AShockRestartsTheWindowInTheSameMapFrame) {
  // 100 m/s^2 for 50 ms: the IMU claims a 5 m/s change of velocity that the camera does not see.
  const io::Recording rec = with_shock(Vec3(100, 0, 0));
  const auto off = testing::run_estimator(rec, {"estimator.failure.detection=false"});
  const auto on = testing::run_estimator(rec, {});
  // Without the detection the estimate follows the IMU and never comes back.
  EXPECT_GT(max_error(off.estimates, rec, 6, 12), 5.0);
  EXPECT_EQ(off.stats.failures, 0u);
  EXPECT_GE(on.stats.failures, 1u);
  EXPECT_GE(on.stats.restarts, 1u);
  EXPECT_EQ(on.stats.map_frame_resets, 0u) << on.stats.last_failure;
  EXPECT_LT(max_error(on.estimates, rec, 0, 6), 0.05);
  // Same W before and after: measured with the alignment of the start.
  EXPECT_LT(max_error(on.estimates, rec, 6, 12), 0.5) << on.stats.last_failure;
  // Every frame still gets an estimate, in order.
  EXPECT_EQ(on.estimates.size(), off.estimates.size());
  for (std::size_t i = 1; i < on.estimates.size(); ++i) EXPECT_GT(on.estimates[i].t, on.estimates[i - 1].t);
}

TEST(SlidingWindowFailure, RestartsAreDeterministic) {
  const io::Recording rec = with_shock(Vec3(100, 0, 0));
  const auto a = testing::run_estimator(rec, {});
  const auto b = testing::run_estimator(rec, {});
  ASSERT_EQ(a.estimates.size(), b.estimates.size());
  for (std::size_t i = 0; i < a.estimates.size(); ++i) {
    EXPECT_EQ(a.estimates[i].T_W_B.t, b.estimates[i].T_W_B.t) << i;
    EXPECT_EQ(a.estimates[i].covariance, b.estimates[i].covariance) << i;
  }
}

TEST(SlidingWindowFailure, WithoutARecentGoodEstimateItInitializesInANewMapFrame) {
  // No confirmed estimate is recent enough to restart from: the window initializes again by HPnP
  // (the still start cannot be repeated while walking), in a W of its own.
  const io::Recording rec = with_shock(Vec3(100, 0, 0));
  const auto run = testing::run_estimator(rec, {"estimator.failure.restart_max_gap=0.01"});
  EXPECT_GE(run.stats.failures, 1u);
  EXPECT_EQ(run.stats.restarts, 0u);
  EXPECT_EQ(run.stats.map_frame_resets, 1u) << run.stats.last_failure;
  const double reinit_s = run.stats.initialized_at_s - ns_to_seconds(rec.features.front().t);
  EXPECT_GT(reinit_s, 6.0);
  EXPECT_LT(reinit_s, 9.0);
  std::size_t initializing_after_shock = 0;
  for (const auto& e : run.estimates)
    if (ns_to_seconds(e.t - rec.features.front().t) > 6.1 && e.mode == EstimatorMode::kInitializing)
      ++initializing_after_shock;
  EXPECT_GT(initializing_after_shock, 0u);
  // In its new W the estimate tracks again.
  EXPECT_LT(max_error(run.estimates, rec, reinit_s, 12, reinit_s), 0.1);
}

}  // namespace
}  // namespace navaid::estimation
