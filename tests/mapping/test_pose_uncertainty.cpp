// Pose uncertainty from the estimate's covariance, and the gate that keeps unsure frames out.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "navaid/core/errors.hpp"
#include "navaid/mapping/pose_uncertainty.hpp"
#include "test_support.hpp"

namespace navaid::mapping {
namespace {

StateEstimate estimate(double sigma_x, double sigma_y, double sigma_yaw_body, double pitch = 0.0) {
  StateEstimate e;
  e.mode = EstimatorMode::kRgbdVio;
  e.T_W_B = SE3(Quat(Eigen::AngleAxisd(pitch, Vec3::UnitY())), Vec3(1, 2, 3));
  e.covariance = Mat15::Identity() * 1e-6;
  e.covariance(2, 2) = sigma_yaw_body * sigma_yaw_body;
  e.covariance(3, 3) = sigma_x * sigma_x;
  e.covariance(4, 4) = sigma_y * sigma_y;
  return e;
}

TEST(PoseUncertainty, WorstHorizontalDirectionAndYawAboutGravity) {
  const auto u = pose_uncertainty(estimate(0.1, 0.3, 0.05));
  EXPECT_NEAR(u.sigma_xy, 0.3, 1e-12);
  EXPECT_NEAR(u.sigma_z, 1e-3, 1e-12);
  EXPECT_NEAR(u.sigma_yaw, 0.05, 1e-6);
  // Correlated x-y: the largest eigenvalue, not the larger diagonal entry.
  StateEstimate e = estimate(0.2, 0.2, 0.01);
  e.covariance(3, 4) = e.covariance(4, 3) = 0.03;  // eigenvalues 0.04 +- 0.03
  EXPECT_NEAR(pose_uncertainty(e).sigma_xy, std::sqrt(0.07), 1e-12);
}

TEST(PoseUncertainty, BodyRotationErrorIsMovedIntoTheWorld) {
  // Pitched 90 deg about y: the body z axis lies along W's x, so body-z error is no yaw error, and
  // the body x axis lies along W's -z, so body-x error is all yaw.
  StateEstimate e = estimate(0.1, 0.1, 0.2, M_PI / 2);
  EXPECT_NEAR(pose_uncertainty(e).sigma_yaw, 1e-3, 1e-6);
  e.covariance(0, 0) = 0.04;
  EXPECT_NEAR(pose_uncertainty(e).sigma_yaw, 0.2, 1e-6);
}

TEST(PoseUncertainty, BadCovariancesAreClearErrors) {
  StateEstimate e = estimate(0.1, 0.1, 0.01);
  e.t = 42;
  e.covariance(3, 3) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(navaid::testing::error_message<Error>([&] { pose_uncertainty(e); }).find("t = 42 ns: position covariance is not finite"),
            std::string::npos);
  e = estimate(0.1, 0.1, 0.01);
  e.covariance(3, 3) = -0.01;
  EXPECT_NE(navaid::testing::error_message<Error>([&] { pose_uncertainty(e); }).find("not positive definite"), std::string::npos);
  e = estimate(0.1, 0.1, 0.01);
  e.covariance(0, 1) = 0.5;
  EXPECT_NE(navaid::testing::error_message<Error>([&] { pose_uncertainty(e); }).find("not symmetric"), std::string::npos);
}

TEST(MappingGate, ModesAndLimits) {
  const MappingGateConfig g;  // 0.5 m, 5 deg
  StateEstimate e = estimate(0.1, 0.1, 0.01);
  EXPECT_EQ(gate(e, pose_uncertainty(e), g), GateDecision::kMap);
  for (const auto mode : {EstimatorMode::kInitializing, EstimatorMode::kLost}) {
    e.mode = mode;
    EXPECT_EQ(gate(e, pose_uncertainty(e), g), GateDecision::kSkipMode);
  }
  for (const auto mode : {EstimatorMode::kVio, EstimatorMode::kImuOnly}) {
    e.mode = mode;
    EXPECT_EQ(gate(e, pose_uncertainty(e), g), GateDecision::kMap);
  }
  StateEstimate far = estimate(0.6, 0.1, 0.01);
  EXPECT_EQ(gate(far, pose_uncertainty(far), g), GateDecision::kSkipUncertain);
  StateEstimate turned = estimate(0.1, 0.1, 6.0 * M_PI / 180.0);
  EXPECT_EQ(gate(turned, pose_uncertainty(turned), g), GateDecision::kSkipUncertain);
  const auto cfg = read_mapping_gate_config(Config::parse("mapping: {gate: {max_sigma_yaw_deg: 10}}"));
  EXPECT_EQ(gate(turned, pose_uncertainty(turned), cfg), GateDecision::kMap);
}

}  // namespace
}  // namespace navaid::mapping
